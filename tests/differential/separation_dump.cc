// SPDX-License-Identifier: Apache-2.0
// Prints what ispq's separation search finds on one quantization, one JSON object per violation,
// for the differential harness (tests/differential/README.md), which compares it with the
// upstream implementation's rows on the same q.
//
//   ispq_separation_dump --tmesh F.tmesh.json --q Q.json [--reference_block_boxes]
//
// Q.json is any JSON object with an integer array "q" (a result file, or the harness's own).
#include <iostream>
#include <string>

#include "absl/flags/flag.h"
#include "absl/flags/parse.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "core/proto/tmesh_file.h"
#include "core/proto/tmesh_from_proto.h"
#include "core/quantization_validator.h"
#include "core/read_file.h"
#include "google/protobuf/struct.pb.h"
#include "google/protobuf/util/json_util.h"

ABSL_FLAG(std::string, tmesh, "", "the T-mesh file");
ABSL_FLAG(std::string, q, "", "a JSON file with an integer array \"q\"");
ABSL_FLAG(bool, reference_block_boxes, false, "the reference's unsorted block boxes");

namespace {

std::string RowJson(const ispq::SeparationRow& row) {
  std::string text = "[";
  for (size_t i = 0; i < row.terms.size(); ++i) {
    absl::StrAppend(&text, i ? "," : "", "[", row.terms[i].coef, ",", row.terms[i].var, "]");
  }
  return text + "]";
}

const char* KindName(ispq::SeparationTargetKind kind) {
  switch (kind) {
    case ispq::SeparationTargetKind::kNode:
      return "node";
    case ispq::SeparationTargetKind::kArc:
      return "arc";
    case ispq::SeparationTargetKind::kPatch:
      return "patch";
  }
  return "?";
}

}  // namespace

int main(int argc, char** argv) {
  absl::ParseCommandLine(argc, argv);
  absl::StatusOr<ispq::TMeshMessage> proto = ispq::ReadTMeshFile(absl::GetFlag(FLAGS_tmesh));
  if (!proto.ok()) {
    std::cerr << proto.status() << "\n";
    return 2;
  }
  absl::StatusOr<ispq::TMesh> mesh = ispq::TMeshFromProto(proto->get());
  if (!mesh.ok()) {
    std::cerr << mesh.status() << "\n";
    return 2;
  }
  absl::StatusOr<std::string> text =
      ispq::ReadFileToString(absl::GetFlag(FLAGS_q), ispq::kMaxTMeshFileBytes);
  google::protobuf::Struct object;
  if (!text.ok() || !google::protobuf::util::JsonStringToMessage(*text, &object).ok() ||
      !object.fields().contains("q")) {
    std::cerr << "cannot read an array \"q\" from " << absl::GetFlag(FLAGS_q) << "\n";
    return 2;
  }
  std::vector<int64_t> q;
  for (const google::protobuf::Value& v : object.fields().at("q").list_value().values()) {
    q.push_back(static_cast<int64_t>(v.number_value()));
  }
  ispq::ValidationOptions options;
  if (absl::GetFlag(FLAGS_reference_block_boxes)) {
    options.separation = ispq::SeparationRule::kReferenceSearch;
  }
  absl::StatusOr<ispq::ValidationReport> report = ispq::ValidateQuantization(*mesh, q, options);
  if (!report.ok()) {
    std::cerr << report.status() << "\n";
    return 2;
  }
  std::cout << "{\"consistent\":" << (report->consistent() ? "true" : "false")
            << ",\"simple_violations\":" << report->simple.size()
            << ",\"separation_checked\":" << (report->separation_checked ? "true" : "false")
            << ",\"valid\":" << (report->valid() ? "true" : "false") << "}\n";
  for (const ispq::SeparationViolation& v : report->separation) {
    std::cout << "{\"start\":\"" << (v.start_dim == ispq::EntityDim::kNode ? "node" : "link")
              << "\",\"entity\":" << v.start_entity << ",\"start_node\":" << v.start_node
              << ",\"sector\":" << v.sector << ",\"target\":\"" << KindName(v.target_kind)
              << "\",\"target_id\":" << v.target << ",\"path\":[" << absl::StrJoin(v.path, ",")
              << "],\"default\":" << RowJson(v.default_row)
              << ",\"failsafe\":" << RowJson(v.failsafe_row) << "}\n";
  }
  return report->valid() ? 0 : 1;
}
