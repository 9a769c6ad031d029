// SPDX-License-Identifier: Apache-2.0
#include "tests/server/server_test_jobs.h"

#include "core/mesh_stats.h"
#include "core/proto/mesh_stats_proto.h"
#include "tests/support/test_data.h"

namespace ispq::server {

JobSpec NotchJobSpec() {
  static const std::shared_ptr<const TMesh> mesh = std::make_shared<const TMesh>(
      testing::LoadTMeshOrDie(testing::RealTMeshPath("hex-me/s07c_notch.tmesh.json")));
  JobSpec spec;
  spec.mesh = mesh;
  spec.mesh_stats = MeshStatsToProto(ComputeMeshStats(*mesh));
  spec.options.scaling = 0.5;
  return spec;
}

std::shared_ptr<Job> NewNotchJob(const std::string& id, absl::Time now) {
  return std::make_shared<Job>(id, NotchJobSpec(), /*bound_to_call=*/false, /*queue_position=*/0,
                               now);
}

}  // namespace ispq::server
