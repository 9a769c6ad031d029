// SPDX-License-Identifier: Apache-2.0
// The web view's geometry (server/http/mesh_geometry.h, geometry_cache.h, geometry_route.h): the
// binary layout decoded back equals the request's nodes and arcs; above the arc limit every
// critical arc and every k-th other is sent and the header says so; the route is the job owner's
// only, answers from the job's mesh while it runs and from the cache after it ended, and says
// clearly when neither is there; a job submitted over HTTP is drawable even after it ended.
#include "server/http/geometry_route.h"

#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "core/arc_bundles.h"
#include "core/consistency_matrix.h"
#include "gmock/gmock.h"
#include "google/protobuf/struct.pb.h"
#include "google/protobuf/util/json_util.h"
#include "gtest/gtest.h"
#include "server/http/job_routes.h"
#include "server/http/mesh_geometry.h"
#include "server/model/mesh_admission.h"
#include "server/model/mesh_positions.h"
#include "tests/server/http/http_test_service.h"

namespace ispq::server::http {
namespace {

using ::testing::HasSubstr;

// The geometry response read back as the page reads it.
struct Decoded {
  std::vector<int32_t> header;
  std::vector<float> positions;
  std::vector<int32_t> arc_ids, ends;
  std::vector<float> lengths;
  std::vector<int32_t> bundles;
  std::vector<uint8_t> flags;
  std::vector<int32_t> patch_ids, offsets, cycle_nodes;
  std::vector<uint8_t> patch_flags;
  std::vector<int32_t> bundle_first_arcs;
};

template <typename T>
std::vector<T> Take(const std::string& bytes, size_t& offset, size_t count) {
  std::vector<T> values(count);
  EXPECT_LE(offset + count * sizeof(T), bytes.size());
  if (offset + count * sizeof(T) > bytes.size()) return {};
  std::memcpy(values.data(), bytes.data() + offset, count * sizeof(T));
  offset += count * sizeof(T);
  return values;
}

Decoded Decode(const std::string& bytes) {
  Decoded d;
  size_t offset = 0;
  d.header = Take<int32_t>(bytes, offset, 8);
  if (d.header.size() != 8) return d;
  const size_t nodes = d.header[1], sent = d.header[3];
  d.positions = Take<float>(bytes, offset, 3 * nodes);
  d.arc_ids = Take<int32_t>(bytes, offset, sent);
  d.ends = Take<int32_t>(bytes, offset, 2 * sent);
  d.lengths = Take<float>(bytes, offset, sent);
  d.bundles = Take<int32_t>(bytes, offset, sent);
  d.flags = Take<uint8_t>(bytes, offset, sent);
  offset += (4 - sent % 4) % 4;  // padding
  const size_t patches = d.header[6], entries = d.header[7];
  d.patch_ids = Take<int32_t>(bytes, offset, patches);
  d.offsets = Take<int32_t>(bytes, offset, patches + 1);
  d.cycle_nodes = Take<int32_t>(bytes, offset, entries);
  d.patch_flags = Take<uint8_t>(bytes, offset, patches);
  offset += (4 - patches % 4) % 4;  // padding
  d.bundle_first_arcs = Take<int32_t>(bytes, offset, d.header[5]);
  EXPECT_EQ(bytes.size(), offset) << "nothing after the bundles' first arcs";
  EXPECT_EQ(bytes.size() % 4, 0u);
  return d;
}

std::string ErrorMessage(const HttpResponse& response) {
  google::protobuf::Struct error;
  EXPECT_TRUE(google::protobuf::util::JsonStringToMessage(response.body, &error).ok());
  return error.fields().at("message").string_value();
}

class GeometryRouteTest : public ::testing::Test {
 protected:
  GeometryRouteTest() : parts_(service_.parts()), cache_(service_.memory) {
    AddJobRoutes(router_, parts_, limits_, &cache_);
    AddGeometryRoute(router_, parts_, cache_);
  }

  HttpResponse Get(const std::string& id, const std::string& principal = "alice") {
    const std::string path = "/v1/jobs/" + id + "/geometry";
    std::string matched;
    const Route* route = router_.Match("GET", path, &matched);
    EXPECT_NE(route, nullptr);
    if (route == nullptr) return HttpResponse();
    EXPECT_TRUE(route->authenticated);
    EXPECT_EQ(route->lane, Lane::kLookup);
    HttpRequest request = RouteRequest("GET", path, matched, principal);
    auto responder = std::make_shared<RecordingResponder>();
    route->handle(request, responder);
    return responder->WaitForAnswer();
  }

  void Cancel(const std::string& name) {
    v1::CancelJobRequest cancel;
    cancel.set_name(name);
    ASSERT_TRUE(service_.service.CancelJob(cancel, Principal{.name = "alice"}).ok());
  }

  static std::string IdOf(const std::string& name) { return name.substr(name.find('/') + 1); }

  HttpTestService service_;
  const HttpLimits limits_;
  const HttpParts parts_;
  GeometryCache cache_;
  Router router_;
};

TEST_F(GeometryRouteTest, TheGeometryIsTheRequestsNodesAndArcs) {
  const v1::QuantizeRequest request = NotchRequest();
  const std::shared_ptr<Job> job = service_.SubmitOrDie(request, "alice");
  const HttpResponse answer = Get(job->id());
  ASSERT_EQ(answer.status, 200) << answer.body;
  EXPECT_EQ(answer.content_type, "application/octet-stream");

  const v1::TMesh& mesh = request.mesh();
  const Decoded d = Decode(answer.body);
  ASSERT_EQ(d.header.size(), 8u);
  EXPECT_EQ(d.header[0], kGeometryMagic);
  EXPECT_EQ(d.header[1], mesh.nodes_size());
  EXPECT_EQ(d.header[2], mesh.arcs_size());
  EXPECT_EQ(d.header[3], mesh.arcs_size()) << "a small mesh is sent whole";
  EXPECT_EQ(d.header[4], 1);
  EXPECT_GT(d.header[5], 0);
  ASSERT_EQ(d.positions.size(), 3u * mesh.nodes_size());
  for (int n = 0; n < mesh.nodes_size(); ++n) {
    for (int i = 0; i < 3; ++i) {
      EXPECT_EQ(d.positions[3 * n + i], static_cast<float>(mesh.nodes(n).position(i)))
          << "node " << n;
    }
  }
  ASSERT_EQ(d.arc_ids.size(), static_cast<size_t>(mesh.arcs_size()));
  for (int a = 0; a < mesh.arcs_size(); ++a) {
    EXPECT_EQ(d.arc_ids[a], a);
    EXPECT_EQ(d.ends[2 * a], mesh.arcs(a).from()) << "arc " << a;
    EXPECT_EQ(d.ends[2 * a + 1], mesh.arcs(a).to()) << "arc " << a;
    EXPECT_EQ(d.lengths[a], static_cast<float>(mesh.arcs(a).length())) << "arc " << a;
    EXPECT_EQ((d.flags[a] & kGeometryCritical) != 0, mesh.arcs(a).critical()) << "arc " << a;
    EXPECT_EQ((d.flags[a] & kGeometrySingular) != 0, mesh.arcs(a).singular() != 0) << "arc " << a;
    EXPECT_EQ((d.flags[a] & kGeometryBoundary) != 0, mesh.arcs(a).boundary()) << "arc " << a;
    EXPECT_GE(d.bundles[a], 0);
    EXPECT_LT(d.bundles[a], d.header[5]);
  }
  // Every patch, as the nodes its halfarcs leave, in cycle order.
  ASSERT_EQ(d.patch_ids.size(), static_cast<size_t>(mesh.patches_size()));
  for (int p = 0; p < mesh.patches_size(); ++p) {
    EXPECT_EQ(d.patch_ids[p], p);
    const auto& cycle = mesh.patches(p).halfarcs();
    ASSERT_EQ(d.offsets[p + 1] - d.offsets[p], cycle.size()) << "patch " << p;
    for (int i = 0; i < cycle.size(); ++i) {
      const v1::Arc& arc = mesh.arcs(cycle[i] / 2);
      EXPECT_EQ(d.cycle_nodes[d.offsets[p] + i], cycle[i] % 2 == 0 ? arc.from() : arc.to())
          << "patch " << p << " halfarc " << cycle[i];
    }
    EXPECT_EQ((d.patch_flags[p] & kGeometryBoundary) != 0, mesh.patches(p).boundary());
  }
}

TEST_F(GeometryRouteTest, AboveTheLimitEveryCriticalArcAndEveryKthOtherIsSent) {
  const v1::QuantizeRequest request = NotchRequest();
  absl::StatusOr<AdmittedMesh> admitted = AdmitMesh(request.mesh(), 1000000);
  ASSERT_TRUE(admitted.ok()) << admitted.status();
  const TMesh& mesh = *admitted->mesh;
  const NodePositions* positions = NodePositionsOf(admitted->mesh);
  ASSERT_NE(positions, nullptr);
  int critical = 0;
  for (ArcId a = 0; a < mesh.num_arcs(); ++a) critical += mesh.arc_critical(a) ? 1 : 0;
  const int others = mesh.num_arcs() - critical;
  ASSERT_GT(others, 4) << "the notch has regular arcs to drop";

  const int limit = critical + 2;
  const Decoded d = Decode(EncodeMeshGeometry(mesh, *positions, limit));
  ASSERT_EQ(d.header.size(), 8u);
  const int stride = d.header[4];
  EXPECT_EQ(stride, (others + 1) / 2) << "the smallest stride that fits the limit";
  const int sent_others = (others + stride - 1) / stride;
  EXPECT_EQ(d.header[3], critical + sent_others);
  EXPECT_LE(d.header[3], limit);
  EXPECT_EQ(d.header[2], mesh.num_arcs()) << "the header names what was left out";
  int seen_critical = 0;
  for (size_t i = 0; i < d.arc_ids.size(); ++i) {
    if (i > 0) {
      EXPECT_LT(d.arc_ids[i - 1], d.arc_ids[i]) << "ascending";
    }
    EXPECT_EQ(d.ends[2 * i], mesh.arc_from(d.arc_ids[i]));
    seen_critical += mesh.arc_critical(d.arc_ids[i]) ? 1 : 0;
  }
  EXPECT_EQ(seen_critical, critical) << "every critical arc is drawn";
  // Every bundle's smallest arc, drawn or not: the bundle of any arc a separation row names.
  const ConsistencyMatrix consistency(mesh);
  const ArcBundles bundles(mesh, consistency);
  ASSERT_EQ(d.bundle_first_arcs.size(), static_cast<size_t>(bundles.num_bundles()));
  for (BundleId b = 0; b < bundles.num_bundles(); ++b) {
    EXPECT_EQ(d.bundle_first_arcs[b], bundles.arcs(b)[0]) << "bundle " << b;
  }
  for (size_t i = 0; i < d.arc_ids.size(); ++i) {
    EXPECT_EQ(d.bundle_first_arcs[d.bundles[i]], bundles.arcs(bundles.bundle_of(d.arc_ids[i]))[0]);
  }
  int critical_patches = 0;
  for (PatchId p = 0; p < mesh.num_patches(); ++p) critical_patches += mesh.patch_critical(p);
  EXPECT_EQ(d.header[6], critical_patches) << "a decimated mesh sends its critical patches";
  for (int32_t p : d.patch_ids) EXPECT_TRUE(mesh.patch_critical(p)) << "patch " << p;
}

TEST_F(GeometryRouteTest, OnlyTheOwnerSeesIt) {
  const std::shared_ptr<Job> job = service_.SubmitOrDie(NotchRequest(), "alice");
  EXPECT_EQ(Get(job->id(), "bob").status, 404);
  EXPECT_EQ(Get(job->id(), "admin").status, 200);
  EXPECT_EQ(Get("no-such-job").status, 404);
}

TEST_F(GeometryRouteTest, AfterTheJobEndedItIsAnsweredFromTheCacheOrRefusedClearly) {
  const std::shared_ptr<Job> drawn = service_.SubmitOrDie(NotchRequest(), "alice");
  const HttpResponse first = Get(drawn->id());
  ASSERT_EQ(first.status, 200);
  const std::shared_ptr<Job> never_drawn = service_.SubmitOrDie(NotchRequest(), "alice");
  Cancel(drawn->name());
  Cancel(never_drawn->name());
  ASSERT_EQ(drawn->mesh(), nullptr) << "an ended job lets go of its mesh";

  const HttpResponse again = Get(drawn->id());
  EXPECT_EQ(again.status, 200);
  EXPECT_EQ(again.body, first.body);

  const HttpResponse gone = Get(never_drawn->id());
  EXPECT_EQ(gone.status, 400);
  EXPECT_THAT(ErrorMessage(gone), HasSubstr(never_drawn->name()));
  EXPECT_THAT(ErrorMessage(gone), HasSubstr("no longer holds its mesh"));
  EXPECT_GT(service_.budget.used(MemoryUse::kResults), 0) << "the cache is in the budget";
}

TEST_F(GeometryRouteTest, AJobSubmittedOverHttpIsDrawableAfterItEnded) {
  std::string id;
  const Route* submit = router_.Match("POST", "/v1/jobs", &id);
  ASSERT_NE(submit, nullptr);
  HttpRequest request = RouteRequest("POST", "/v1/jobs");
  request.body = ClientJson(NotchRequest());
  auto responder = std::make_shared<RecordingResponder>();
  submit->handle(request, responder);
  const HttpResponse answer = responder->WaitForAnswer();
  ASSERT_EQ(answer.status, 200) << answer.body;
  google::protobuf::Struct job;
  ASSERT_TRUE(google::protobuf::util::JsonStringToMessage(answer.body, &job).ok());
  const std::string name = job.fields().at("name").string_value();
  Cancel(name);

  const HttpResponse geometry = Get(IdOf(name));
  ASSERT_EQ(geometry.status, 200) << geometry.body;
  EXPECT_EQ(Decode(geometry.body).header[3], NotchRequest().mesh().arcs_size());
}

}  // namespace
}  // namespace ispq::server::http
