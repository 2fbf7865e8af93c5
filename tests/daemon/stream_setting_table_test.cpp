// The stream setting table (daemon/config/stream_setting_table.h) against its surfaces: fq.proto
// by protobuf reflection (every row has its SetParams and ControlReply field, every setting field
// of SetParams has a row), and each row's value through the config file, the control socket's
// messages, validate() and the audit.
#include "daemon/config/stream_setting_table.h"

#include <gtest/gtest.h>

#include <set>
#include <string>

#include "daemon/config/config.h"
#include "daemon/control/settings_audit.h"

namespace fq::daemon {
namespace {

namespace pb = google::protobuf;

pb::FieldDescriptor::CppType wire_type(SettingKind k) {
  switch (k) {
    case SettingKind::kDouble:
      return pb::FieldDescriptor::CPPTYPE_DOUBLE;
    case SettingKind::kInt:
    case SettingKind::kUint:
      return pb::FieldDescriptor::CPPTYPE_UINT32;
    case SettingKind::kEnum:
      break;
  }
  return pb::FieldDescriptor::CPPTYPE_ENUM;
}

// A value in the row's range other than the built-in default.
double other_value(const StreamSettingRow& row) {
  const double now = row.get(StreamSettings{});
  if (row.kind == SettingKind::kEnum) return row.choices[now == row.choices[0].value ? 1 : 0].value;
  return now == row.hi ? row.lo : row.hi;
}

TEST(StreamSettingTable, EveryRowHasItsFieldsAndEverySettingFieldARow) {
  std::set<std::string> rows;
  for (const StreamSettingRow& row : stream_setting_table()) {
    rows.insert(row.name);
    EXPECT_NE(std::string(row.help), "") << row.name;
    const pb::FieldDescriptor* q = wire::SetParams::descriptor()->FindFieldByName(row.name);
    const pb::FieldDescriptor* r = wire::ControlReply::descriptor()->FindFieldByName(row.name);
    ASSERT_NE(q, nullptr) << "SetParams has no field " << row.name;
    ASSERT_NE(r, nullptr) << "ControlReply has no field " << row.name;
    EXPECT_TRUE(q->has_presence()) << row.name << " must be optional: unset keeps the stream's value";
    EXPECT_EQ(q->cpp_type(), wire_type(row.kind)) << row.name;
    EXPECT_EQ(r->cpp_type(), wire_type(row.kind)) << row.name;
    if (row.kind != SettingKind::kEnum) continue;
    std::set<int> numbers;
    for (const ParamChoice& c : row.choices) {
      EXPECT_NE(q->enum_type()->FindValueByNumber(c.wire), nullptr) << row.name << " " << c.name;
      numbers.insert(c.wire);
    }
    EXPECT_EQ(numbers.size(), static_cast<size_t>(q->enum_type()->value_count())) << row.name;
  }
  // SetParams' own fields beside the settings: the stream, its parameters and compute mode
  // (the parameter table's), and `create`, which is about the request.
  const std::set<std::string> not_settings{"stream_id", "params", "compute", "create"};
  const pb::Descriptor* d = wire::SetParams::descriptor();
  for (int i = 0; i < d->field_count(); ++i)
    if (!not_settings.count(d->field(i)->name()))
      EXPECT_TRUE(rows.count(d->field(i)->name()))
          << "SetParams." << d->field(i)->name() << " has no table row";
}

TEST(StreamSettingTable, EachRowCrossesTheWireAlone) {
  for (const StreamSettingRow& row : stream_setting_table()) {
    StreamSettings sent;
    row.set(sent, other_value(row));
    wire::ControlReply reply;
    settings_to_wire(sent, reply);
    // The reply's fields are SetParams' under the same names: the reply sent back as a request.
    wire::SetParams q;
    for (const StreamSettingRow& r : stream_setting_table()) {
      const pb::FieldDescriptor* from = wire::ControlReply::descriptor()->FindFieldByName(r.name);
      const pb::FieldDescriptor* to = wire::SetParams::descriptor()->FindFieldByName(r.name);
      const pb::Reflection* rr = reply.GetReflection();
      const pb::Reflection* qr = q.GetReflection();
      switch (from->cpp_type()) {
        case pb::FieldDescriptor::CPPTYPE_DOUBLE:
          qr->SetDouble(&q, to, rr->GetDouble(reply, from));
          break;
        case pb::FieldDescriptor::CPPTYPE_UINT32:
          qr->SetUInt32(&q, to, rr->GetUInt32(reply, from));
          break;
        default:
          qr->SetEnumValue(&q, to, rr->GetEnumValue(reply, from));
          break;
      }
    }
    StreamSettings got;
    settings_from_wire(q, got);
    EXPECT_EQ(got, sent) << row.name;
    EXPECT_EQ(row.get(got), other_value(row)) << row.name;
  }
}

TEST(StreamSettingTable, EachRowIsReadFromTheConfigFile) {
  for (const StreamSettingRow& row : stream_setting_table()) {
    const double v = other_value(row);
    const std::string value =
        row.kind == SettingKind::kEnum ? "\"" + format_setting(row, v) + "\"" : format_setting(row, v);
    const std::string text = std::string("[defaults") + (row.table ? std::string(".") + row.table : "") +
                             "]\n" + row.name + " = " + value + "\n";
    DaemonConfig c;
    ASSERT_TRUE(parse_config(text, "t.toml", c).ok()) << text;
    EXPECT_EQ(row.get(c.defaults), v) << text;
  }
}

TEST(StreamSettingTable, EachRowIsCheckedAndAudited) {
  for (const StreamSettingRow& row : stream_setting_table()) {
    StreamSettings after;
    row.set(after, other_value(row));
    EXPECT_TRUE(validate(after).ok()) << row.name;
    const std::vector<std::string> changes = settings_changes(StreamSettings{}, after);
    ASSERT_EQ(changes.size(), 1u) << row.name;
    EXPECT_EQ(changes[0].rfind(std::string(row.name) + " ", 0), 0u) << changes[0];
    if (row.kind == SettingKind::kEnum) continue;
    row.set(after, row.hi + 1);
    const Status s = validate(after);
    EXPECT_FALSE(s.ok()) << row.name;
    EXPECT_NE(s.message().find(row.key() + " must be in ["), std::string::npos) << s.message();
  }
}

}  // namespace
}  // namespace fq::daemon
