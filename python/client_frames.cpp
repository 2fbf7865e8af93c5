#include "python/client_frames.h"

#include <google/protobuf/descriptor.h>
#include <google/protobuf/reflection.h>
#include <pybind11/numpy.h>

#include "clients/common/override_options.h"
#include "core/param_table.h"
#include "python/numpy_mesh.h"
#include "python/py_errors.h"

namespace fq::py {

namespace pyb = pybind11;
namespace gp = google::protobuf;

namespace {

// The text fqpub would have been given for this value, so that parse_param checks it.
std::string param_text(const pyb::handle& value) {
  if (pyb::isinstance<pyb::bool_>(value)) return value.cast<bool>() ? "true" : "false";
  return pyb::str(value);
}

pyb::object field_value(const gp::Message& h, const gp::Reflection& r, const gp::FieldDescriptor& f) {
  switch (f.cpp_type()) {
    case gp::FieldDescriptor::CPPTYPE_INT32:
      return pyb::int_(r.GetInt32(h, &f));
    case gp::FieldDescriptor::CPPTYPE_INT64:
      return pyb::int_(r.GetInt64(h, &f));
    case gp::FieldDescriptor::CPPTYPE_UINT32:
      return pyb::int_(r.GetUInt32(h, &f));
    case gp::FieldDescriptor::CPPTYPE_UINT64:
      return pyb::int_(r.GetUInt64(h, &f));
    case gp::FieldDescriptor::CPPTYPE_DOUBLE:
      return pyb::float_(r.GetDouble(h, &f));
    case gp::FieldDescriptor::CPPTYPE_FLOAT:
      return pyb::float_(r.GetFloat(h, &f));
    case gp::FieldDescriptor::CPPTYPE_BOOL:
      return pyb::bool_(r.GetBool(h, &f));
    case gp::FieldDescriptor::CPPTYPE_ENUM:
      return pyb::str(r.GetEnum(h, &f)->name());
    case gp::FieldDescriptor::CPPTYPE_STRING:
      return pyb::str(r.GetString(h, &f));
    default:
      return pyb::none();
  }
}

}  // namespace

client::FrameSpec frame_spec(const std::string& stream, uint32_t chunks, int position_bits, int encode_speed,
                             const std::string& compute, const pyb::dict& overrides) {
  if (stream.empty()) throw pyb::value_error("stream must not be empty");
  client::FrameSpec spec;
  spec.stream_id = stream;
  spec.chunks = chunks;
  spec.position_bits = position_bits;
  spec.encode_speed = encode_speed;
  spec.decode_speed = encode_speed;  // as fqpub: one speed for both
  client::OverrideArgs args;
  args.compute = compute;
  for (const auto& [key, value] : overrides) {
    const std::string name = pyb::str(key);
    const ParamRow* row = find_param(name);
    if (row == nullptr || !row->on(kWire)) throw pyb::type_error("'" + name + "' is not a frame parameter");
    args.given.emplace_back(row, param_text(value));
  }
  throw_if_error(client::to_wire(args, spec.overrides, spec.compute));
  return spec;
}

std::vector<std::string> build_parts(const pyb::handle& v, const pyb::handle& f,
                                     const client::FrameSpec& spec, uint64_t sequence) {
  const Mesh mesh = to_mesh(v, f);
  std::vector<std::string> parts;
  Status s;
  {
    const pyb::gil_scoped_release unlocked;
    s = client::build_frame(mesh.view(), spec, sequence, parts);
  }
  throw_if_error(s);
  return parts;
}

void decode_checked(client::ReceivedResult& r) {
  Status s;
  {
    const pyb::gil_scoped_release unlocked;
    s = client::decode_result(r);
    if (s.ok()) s = client::check_result(r);
  }
  throw_if_error(s);
}

pyb::dict header_dict(const wire::ResultHeader& h) {
  pyb::dict d;
  const gp::Reflection& r = *h.GetReflection();
  const gp::Descriptor& desc = *h.GetDescriptor();
  for (int i = 0; i < desc.field_count(); ++i) {
    const gp::FieldDescriptor& f = *desc.field(i);
    if (!f.is_repeated()) d[pyb::str(f.name())] = field_value(h, r, f);
  }
  pyb::dict timings;
  for (const wire::StageTiming& t : h.timings()) timings[pyb::str(t.name())] = t.ms();
  d["timings"] = timings;
  return d;
}

pyb::dict result_dict(const client::ReceivedResult& r) {
  pyb::dict d;
  d["positions"] = positions_array(r.mesh.positions, pyb::none());
  d["labels"] = r.labels.empty() ? pyb::object(pyb::none()) : pyb::object(labels_array(r.labels));
  const bool mesh_form = r.header.form() == wire::MESH && r.header.status() != wire::ERROR;
  d["faces"] = mesh_form ? pyb::object(faces_array(r.mesh.triangles)) : pyb::object(pyb::none());
  d["header"] = header_dict(r.header);
  return d;
}

}  // namespace fq::py
