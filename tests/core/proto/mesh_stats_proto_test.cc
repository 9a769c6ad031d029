// SPDX-License-Identifier: Apache-2.0
// MeshStatsToProto copies every count into the field of the same name: each count gets a value
// of its own, so a swapped or forgotten field shows, and a field added to the message without a
// count fails the field count.
#include "core/proto/mesh_stats_proto.h"

#include <map>
#include <string>

#include "gtest/gtest.h"

namespace ispq {
namespace {

TEST(MeshStatsProtoTest, EveryCountLandsInTheFieldOfItsName) {
  MeshStats stats;
  const std::map<std::string, int32_t*> counts = {
      {"blocks", &stats.blocks},
      {"patches", &stats.patches},
      {"arcs", &stats.arcs},
      {"nodes", &stats.nodes},
      {"critical_nodes", &stats.critical_nodes},
      {"critical_arcs", &stats.critical_arcs},
      {"critical_patches", &stats.critical_patches},
      {"critical_entities", &stats.critical_entities},
      {"critical_links", &stats.critical_links},
      {"critical_regions", &stats.critical_regions},
      {"consistency_rows", &stats.consistency_rows},
      {"reduced_consistency_rows", &stats.reduced_consistency_rows},
      {"bundles", &stats.bundles},
      {"subproblems", &stats.subproblems},
  };
  int32_t value = 100;
  std::map<std::string, int32_t> expected;
  for (const auto& [name, field] : counts) {
    *field = ++value;
    expected[name] = value;
  }
  const v1::MeshStats proto = MeshStatsToProto(stats);
  const google::protobuf::Descriptor* descriptor = proto.GetDescriptor();
  const google::protobuf::Reflection* reflection = proto.GetReflection();
  ASSERT_EQ(descriptor->field_count(), static_cast<int>(counts.size()));
  for (int i = 0; i < descriptor->field_count(); ++i) {
    const google::protobuf::FieldDescriptor* field = descriptor->field(i);
    ASSERT_TRUE(expected.contains(field->name())) << field->name();
    ASSERT_EQ(field->cpp_type(), google::protobuf::FieldDescriptor::CPPTYPE_INT32);
    EXPECT_EQ(reflection->GetInt32(proto, field), expected[field->name()]) << field->name();
  }
}

}  // namespace
}  // namespace ispq
