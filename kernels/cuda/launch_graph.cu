#include "kernels/cuda/cuda_check.cuh"
#include "kernels/cuda/launch_graph.cuh"

namespace fq::cuda {

void begin_chain(cudaStream_t s) {
  FQ_CUDA_CHECK(cudaStreamBeginCapture(s, cudaStreamCaptureModeThreadLocal));
}

cudaGraph_t end_chain(cudaStream_t s) {
  cudaGraph_t graph = nullptr;
  FQ_CUDA_CHECK(cudaStreamEndCapture(s, &graph));
  return graph;
}

void abandon_chain(cudaStream_t s) {
  cudaStreamCaptureStatus status = cudaStreamCaptureStatusNone;
  if (cudaStreamIsCapturing(s, &status) == cudaSuccess && status != cudaStreamCaptureStatusNone) {
    cudaGraph_t graph = nullptr;
    // An invalidated capture ends with an error and maybe no graph: either way it is over.
    if (cudaStreamEndCapture(s, &graph) == cudaSuccess && graph != nullptr) cudaGraphDestroy(graph);
  }
  (void)cudaGetLastError();  // the failed launch's error is the one already thrown
}

void install_chain(cudaGraphExec_t& exec, cudaGraph_t graph) {
  if (exec != nullptr) {
    cudaGraphExecUpdateResultInfo info{};
    if (cudaGraphExecUpdate(exec, graph, &info) == cudaSuccess) {
      FQ_CUDA_CHECK(cudaGraphDestroy(graph));
      return;
    }
    (void)cudaGetLastError();  // a chain of another shape: instantiated anew below
    destroy_chain(exec);
    exec = nullptr;
  }
  const cudaError_t made = cudaGraphInstantiate(&exec, graph, 0);
  cudaGraphDestroy(graph);
  if (made != cudaSuccess) exec = nullptr;
  FQ_CUDA_CHECK(made);
}

void replay_chain(cudaGraphExec_t exec, cudaStream_t s) { FQ_CUDA_CHECK(cudaGraphLaunch(exec, s)); }

void destroy_chain(cudaGraphExec_t exec) {
  if (exec != nullptr) cudaGraphExecDestroy(exec);
}

}  // namespace fq::cuda
