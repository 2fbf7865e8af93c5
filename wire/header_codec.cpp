// Strict protobuf parsing: the version first, then unknown fields and enum values are errors.
#include "wire/header_codec.h"

#include <google/protobuf/descriptor.h>
#include <google/protobuf/unknown_field_set.h>

#include <string>
#include <vector>

namespace fq::wire {
namespace {

using google::protobuf::FieldDescriptor;
using google::protobuf::Message;

std::string check_field(const Message& m, const FieldDescriptor* f, const std::string& prefix);

/// First thing in `m` this build does not understand ("" when none): proto3 keeps unknown
/// fields and open enums keep unknown values, so both must be looked for explicitly, at any depth.
std::string find_unknown(const Message& m, const std::string& prefix) {
  const auto* r = m.GetReflection();
  const auto& unknown = r->GetUnknownFields(m);
  if (!unknown.empty()) {
    return "unknown field number " + std::to_string(unknown.field(0).number()) + " in " + prefix +
           m.GetDescriptor()->name();
  }
  std::vector<const FieldDescriptor*> fields;
  r->ListFields(m, &fields);
  for (const auto* f : fields) {
    std::string problem = check_field(m, f, prefix);
    if (!problem.empty()) return problem;
  }
  return {};
}

std::string check_field(const Message& m, const FieldDescriptor* f, const std::string& prefix) {
  const auto* r = m.GetReflection();
  const int n = f->is_repeated() ? r->FieldSize(m, f) : 1;
  for (int i = 0; i < n; ++i) {
    if (f->cpp_type() == FieldDescriptor::CPPTYPE_MESSAGE) {
      const Message& sub = f->is_repeated() ? r->GetRepeatedMessage(m, f, i) : r->GetMessage(m, f);
      std::string problem = find_unknown(sub, prefix + f->name() + ".");
      if (!problem.empty()) return problem;
    } else if (f->cpp_type() == FieldDescriptor::CPPTYPE_ENUM) {
      const int v = f->is_repeated() ? r->GetRepeatedEnumValue(m, f, i) : r->GetEnumValue(m, f);
      if (f->enum_type()->FindValueByNumber(v) == nullptr) {
        return "value " + std::to_string(v) + " of " + prefix + f->name() + " is not a " +
               f->enum_type()->name();
      }
    }
  }
  return {};
}

fq::Status parse_bytes(std::string_view bytes, Message& out, std::string_view what) {
  out.Clear();
  if (!out.ParseFromArray(bytes.data(), static_cast<int>(bytes.size()))) {
    return invalid_input(std::string(what) + ": not a valid " + out.GetDescriptor()->full_name() + " (" +
                         std::to_string(bytes.size()) + " bytes)");
  }
  return {};
}

fq::Status check_known(const Message& m, std::string_view what) {
  std::string problem = find_unknown(m, "");
  if (problem.empty()) return {};
  return invalid_input(std::string(what) + ": " + problem + " (sender speaks a newer protocol?)");
}

/// Parses a message that carries `version`. The version is checked before the fields: a
/// message of another version may have fields this one does not know, and the version
/// mismatch is the message its sender needs.
template <class M>
fq::Status parse_versioned(std::string_view bytes, M& out, std::string_view what) {
  if (auto s = parse_bytes(bytes, out, what); !s.ok()) return s;
  if (out.version() != kWireVersion) {
    return invalid_input(std::string(what) + ": wire version " + std::to_string(out.version()) +
                         " not supported (this build speaks version " + std::to_string(kWireVersion) + ")");
  }
  return check_known(out, what);
}

}  // namespace

fq::Status parse_strict(std::string_view bytes, Message& out, std::string_view what) {
  if (auto s = parse_bytes(bytes, out, what); !s.ok()) return s;
  return check_known(out, what);
}

fq::Status parse_frame_header(std::string_view bytes, FrameHeader& out) {
  if (auto s = parse_versioned(bytes, out, "frame header"); !s.ok()) return s;
  if (out.stream_id().empty()) return invalid_input("frame header: empty stream id");
  if (out.chunk_count() == 0 || out.chunk_count() > kMaxChunks) {
    return invalid_input("frame header: chunk_count " + std::to_string(out.chunk_count()) + " outside [1, " +
                         std::to_string(kMaxChunks) + "]");
  }
  return {};
}

fq::Status parse_result_header(std::string_view bytes, ResultHeader& out) {
  if (auto s = parse_versioned(bytes, out, "result header"); !s.ok()) return s;
  if (out.stream_id().empty()) return invalid_input("result header: empty stream id");
  if (!out.labels().empty() && static_cast<uint32_t>(out.labels_size()) != out.vertex_count()) {
    return invalid_input("result header: " + std::to_string(out.labels_size()) + " labels for " +
                         std::to_string(out.vertex_count()) + " vertices");
  }
  return {};
}

fq::Status parse_control_request(std::string_view bytes, ControlRequest& out) {
  if (auto s = parse_versioned(bytes, out, "control request"); !s.ok()) return s;
  if (out.request_case() == ControlRequest::REQUEST_NOT_SET) {
    return invalid_input("control request: no request set");
  }
  return {};
}

fq::Status parse_control_reply(std::string_view bytes, ControlReply& out) {
  return parse_versioned(bytes, out, "control reply");
}

}  // namespace fq::wire
