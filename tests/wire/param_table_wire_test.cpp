// The parameter table (core/param_table.h) against fq.proto, by protobuf reflection: every
// row with a wire surface has a ParamOverrides field of its name and kind (an enum's names
// with the wire's numbers), every ParamOverrides field has a row, and each row's value
// crosses the wire and comes back.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "core/param_table.h"
#include "tests/support/param_values.h"
#include "wire/header_codec.h"

namespace fq::wire {
namespace {

namespace pb = google::protobuf;

pb::FieldDescriptor::CppType wire_type(ParamKind k) {
  switch (k) {
    case ParamKind::kFloat:
      return pb::FieldDescriptor::CPPTYPE_FLOAT;
    case ParamKind::kUint:
      return pb::FieldDescriptor::CPPTYPE_UINT32;
    case ParamKind::kBool:
      return pb::FieldDescriptor::CPPTYPE_BOOL;
    case ParamKind::kEnum:
      break;
  }
  return pb::FieldDescriptor::CPPTYPE_ENUM;
}

TEST(ParamTableWire, EveryWireRowHasItsFieldAndEveryFieldARow) {
  const pb::Descriptor* d = ParamOverrides::descriptor();
  std::set<std::string> rows;
  for (const ParamRow& row : param_table()) {
    if (!row.on(kWire)) continue;
    rows.insert(row.name);
    const pb::FieldDescriptor* f = d->FindFieldByName(row.name);
    ASSERT_NE(f, nullptr) << "ParamOverrides has no field " << row.name;
    EXPECT_TRUE(f->has_presence()) << row.name << " must be optional: unset keeps the stream's value";
    EXPECT_EQ(f->cpp_type(), wire_type(row.kind)) << row.name;
    if (row.kind != ParamKind::kEnum) continue;
    // Each name has a wire number of the field's enum other than *_DEFAULT (0), and each
    // such number has a name.
    std::set<int> numbers;
    for (const ParamChoice& c : row.choices) {
      EXPECT_NE(f->enum_type()->FindValueByNumber(c.wire), nullptr) << row.name << " " << c.name;
      EXPECT_NE(c.wire, 0) << row.name << " " << c.name;
      numbers.insert(c.wire);
    }
    for (int i = 0; i < f->enum_type()->value_count(); ++i)
      if (f->enum_type()->value(i)->number() != 0)
        EXPECT_TRUE(numbers.count(f->enum_type()->value(i)->number())) << f->enum_type()->value(i)->name();
  }
  for (int i = 0; i < d->field_count(); ++i)
    EXPECT_TRUE(rows.count(d->field(i)->name()))
        << "ParamOverrides." << d->field(i)->name() << " has no table row";
}

TEST(ParamTableWire, EachRowCrossesTheWireAlone) {
  for (const ParamRow& row : param_table()) {
    if (!row.on(kWire)) continue;
    Params sent;
    row.set(sent, test::other_value(row));
    ParamOverrides all;
    params_to_wire(sent, all);
    ParamOverrides one;  // only this row's field: the receiver keeps its other values
    std::optional<double> v;
    ASSERT_TRUE(wire_value(row, all, v).ok());
    ASSERT_TRUE(v.has_value()) << row.name;
    set_wire_value(row, *v, one);
    ParamOverrides via_bytes;
    ASSERT_TRUE(via_bytes.ParseFromString(one.SerializeAsString()));
    Params got;
    ASSERT_TRUE(apply_overrides(via_bytes, got).ok()) << row.name;
    EXPECT_EQ(row.get(got), test::other_value(row)) << row.name;
    for (const ParamRow& other : param_table())
      if (&other != &row)
        EXPECT_EQ(other.get(got), other.get(Params{})) << row.name << " changed " << other.name;
  }
}

TEST(ParamTableWire, EnumsKeepTheWireNumbers) {
  Params p;
  p.filtering.method = FilterMethod::kQuadricRefined;
  p.clustering.geometry = ClusterGeometry::kAuto;
  ParamOverrides w;
  params_to_wire(p, w);
  EXPECT_EQ(w.mode(), QF_PLUS);
  EXPECT_EQ(w.cluster_geometry(), GEOMETRY_AUTO);
  EXPECT_EQ(to_wire(FilterMethod::kBilateral), BF);
  EXPECT_EQ(to_wire(ClusterMethod::kEuclidean), EUCLIDEAN);
}

}  // namespace
}  // namespace fq::wire
