// libFuzzer target: the strict protobuf parsers of every wire message fqd reads or a
// client reads from fqd (frame, result and control headers).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "wire/header_codec.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  fq::wire::FrameHeader f;
  (void)fq::wire::parse_frame_header(bytes, f);
  fq::wire::ResultHeader r;
  (void)fq::wire::parse_result_header(bytes, r);
  fq::wire::ControlRequest q;
  (void)fq::wire::parse_control_request(bytes, q);
  fq::wire::ControlReply p;
  (void)fq::wire::parse_control_reply(bytes, p);
  return 0;
}
