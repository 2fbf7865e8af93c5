// Base of the classes that own something which must neither be duplicated nor change address
// (threads that capture `this`, sockets, CUDA streams and events, a terminal line): deriving
// from it deletes their copies, and since such a class then gets no implicit move either,
// it is pinned where it was made. A class that wants moves declares them itself.
#pragma once

namespace fq {

class NonCopyable {
 public:
  NonCopyable(const NonCopyable&) = delete;
  NonCopyable& operator=(const NonCopyable&) = delete;

 protected:
  NonCopyable() = default;
  ~NonCopyable() = default;
};

}  // namespace fq
