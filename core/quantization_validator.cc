// SPDX-License-Identifier: Apache-2.0
#include "core/quantization_validator.h"

#include <optional>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "core/block_extents.h"
#include "core/consistency_matrix.h"
#include "core/quantization_limits.h"

namespace ispq {
namespace {

const char* AxisName(int axis) {
  static const char* const kNames[] = {"u", "v", "w"};
  return axis >= 0 && axis < 3 ? kNames[axis] : "?";
}

const char* TargetName(SeparationTargetKind kind) {
  switch (kind) {
    case SeparationTargetKind::kNode:
      return "node";
    case SeparationTargetKind::kArc:
      return "arc";
    case SeparationTargetKind::kPatch:
      return "patch";
  }
  return "?";
}

std::string DescribeSimple(const SimpleRow& row, int64_t value) {
  switch (row.kind) {
    case SimpleRowKind::kArcLowerBound:
      return absl::StrCat("arc ", row.element, " has length ", value, " below the lower bound ",
                          row.row.rhs);
    case SimpleRowKind::kLink:
      return absl::StrCat("link (entity ", row.element, ") has length ", value);
    case SimpleRowKind::kRegion:
      return absl::StrCat("region (entity ", row.element, ") has total arc length ", value);
    case SimpleRowKind::kBlockExtent:
      return absl::StrCat("block ", row.element, " has negative extent ", value, " along ",
                          AxisName(row.axis));
  }
  return "unknown simple row";
}

std::string DescribeSeparation(const SeparationViolation& v) {
  const std::string start =
      v.start_dim == EntityDim::kNode
          ? absl::StrCat("critical node ", v.start_node)
          : absl::StrCat("link (entity ", v.start_entity, ", sector ", v.sector, ")");
  return absl::StrCat(start, " touches ", TargetName(v.target_kind), " ", v.target, " (path ",
                      v.path.size(), " halfarcs, ",
                      v.found_by == BlockBoxMode::kSorted ? "sorted" : "reference", " search)");
}

}  // namespace

std::string ValidationReport::Describe(int max_lines) const {
  std::vector<std::string> lines;
  for (ArcId a : out_of_range) {
    lines.push_back(
        absl::StrCat("arc ", a, ": length outside the representable range +-", kMaxArcLength));
  }
  if (hexes_overflow) lines.push_back("the hex count does not fit a 64-bit integer");
  for (const ConsistencyViolation& c : consistency) {
    lines.push_back(absl::StrCat("patch ", c.patch, " axis ", AxisName(c.axis),
                                 ": sides differ by ", c.difference));
  }
  for (size_t i = 0; i < simple.size(); ++i) {
    lines.push_back(DescribeSimple(simple[i], i < simple_values.size() ? simple_values[i] : 0));
  }
  for (const SeparationViolation& v : separation) lines.push_back(DescribeSeparation(v));

  std::string text;
  if (max_lines <= 0) return text;
  const size_t total = lines.size();
  const size_t shown = total <= static_cast<size_t>(max_lines) ? total : max_lines - 1;
  for (size_t i = 0; i < shown; ++i) absl::StrAppend(&text, lines[i], "\n");
  if (shown < total) absl::StrAppend(&text, "... and ", total - shown, " more problems\n");
  return text;
}

namespace {

// The validator with `separation` if given, else with a check of its own, built only when q gets
// as far as the search.
absl::StatusOr<ValidationReport> Validate(const TMesh& mesh, std::span<const int64_t> q,
                                          const ValidationOptions& options,
                                          SeparationCheck* separation) {
  if (static_cast<int64_t>(q.size()) != mesh.num_arcs()) {
    return absl::InvalidArgumentError(absl::StrCat(
        "the quantization has ", q.size(), " entries but the mesh has ", mesh.num_arcs(), " arcs"));
  }
  ValidationReport report;
  for (ArcId a = 0; a < mesh.num_arcs(); ++a) {
    if (q[a] > kMaxArcLength || q[a] < -kMaxArcLength) report.out_of_range.push_back(a);
  }
  if (!report.out_of_range.empty()) return report;
  const ConsistencyMatrix consistency(mesh);
  for (int r = 0; r < consistency.num_rows(); ++r) {
    const int64_t difference = consistency.RowValue(r, q);
    if (difference != 0) {
      report.consistency.push_back(
          {consistency.row_info(r).patch, consistency.row_info(r).axis, difference});
    }
  }
  for (SimpleRow& row : BuildSimpleRows(mesh, options.per_arc_lower_bound)) {
    const int64_t value = row.row.Evaluate(q);
    if (value >= row.row.rhs) continue;
    report.simple.push_back(std::move(row));
    report.simple_values.push_back(value);
  }
  // The search assumes well-defined integer positions and a non-degenerate start box.
  if (report.consistency.empty() && report.simple.empty()) {
    std::optional<SeparationCheck> own;
    if (separation == nullptr) separation = &own.emplace(mesh, options.separation);
    report.separation = separation->FindAllViolations(q);
    report.separation_checked = true;
    report.hexes_overflow = !HexCount(mesh, q).has_value();
  }
  return report;
}

}  // namespace

absl::StatusOr<ValidationReport> ValidateQuantization(const TMesh& mesh, std::span<const int64_t> q,
                                                      const ValidationOptions& options) {
  return Validate(mesh, q, options, nullptr);
}

absl::StatusOr<ValidationReport> ValidateQuantization(const TMesh& mesh, std::span<const int64_t> q,
                                                      const ValidationOptions& options,
                                                      SeparationCheck& separation) {
  if (&separation.mesh() != &mesh || separation.rule() != options.separation) {
    return absl::InvalidArgumentError(
        "the separation check was built for another mesh or separation rule");
  }
  return Validate(mesh, q, options, &separation);
}

}  // namespace ispq
