// SPDX-License-Identifier: Apache-2.0
#include "core/separation_check.h"

#include <algorithm>
#include <iterator>
#include <utility>

namespace ispq {

SeparationCheck::SeparationCheck(const TMesh& mesh, SeparationRule rule)
    : mesh_(&mesh), rule_(rule) {}

std::vector<SeparationSearch>& SeparationCheck::Searches() {
  if (!searches_.empty()) return searches_;
  searches_.reserve(2);
  searches_.emplace_back(*mesh_, SeparationSearchOptions{BlockBoxMode::kReferenceUnsorted});
  if (rule_ == SeparationRule::kBothSearches) {
    searches_.emplace_back(*mesh_, searches_.front(),
                           SeparationSearchOptions{BlockBoxMode::kSorted});
  }
  return searches_;
}

std::vector<SeparationViolation> SeparationCheck::FindFirstViolations(std::span<const int64_t> q) {
  std::vector<SeparationViolation> violations;
  FindFirstViolations(q, [&](SeparationViolation& v) {
    violations.push_back(std::move(v));
    return true;
  });
  return violations;
}

int64_t SeparationCheck::FindFirstViolations(
    std::span<const int64_t> q, const std::function<bool(SeparationViolation&)>& sink) {
  for (SeparationSearch& search : Searches()) {
    const int64_t found = search.FindViolations(q, sink);
    if (found > 0) return found;
  }
  // No sink call, so no search was stopped: every one ran to its end and found nothing.
  clean_q_.assign(q.begin(), q.end());
  has_clean_q_ = true;
  return 0;
}

std::vector<SeparationViolation> SeparationCheck::FindAllViolations(std::span<const int64_t> q) {
  std::vector<SeparationViolation> all;
  if (has_clean_q_ && std::equal(q.begin(), q.end(), clean_q_.begin(), clean_q_.end())) return all;
  for (SeparationSearch& search : Searches()) {
    std::vector<SeparationViolation> violations = search.FindViolations(q);
    all.insert(all.end(), std::make_move_iterator(violations.begin()),
               std::make_move_iterator(violations.end()));
  }
  return all;
}

}  // namespace ispq
