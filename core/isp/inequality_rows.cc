// SPDX-License-Identifier: Apache-2.0
#include "core/isp/inequality_rows.h"

#include <algorithm>

namespace ispq {

InequalityRows::InequalityRows(int num_bundles) : rows_of_bundle_(num_bundles) {}

uint64_t InequalityRows::Hash(std::span<const LinearTerm> terms, int64_t rhs) {
  // FNV-1a over the row's integers; collisions are resolved by comparing rows.
  uint64_t h = 1469598103934665603ull;
  auto mix = [&h](uint64_t x) {
    h ^= x;
    h *= 1099511628211ull;
  };
  mix(static_cast<uint64_t>(rhs));
  for (const LinearTerm& t : terms) {
    mix(static_cast<uint32_t>(t.var));
    mix(static_cast<uint32_t>(t.coef));
  }
  return h;
}

int32_t InequalityRows::Find(std::span<const LinearTerm> terms, int64_t rhs) const {
  const auto it = first_with_hash_.find(Hash(terms, rhs));
  if (it == first_with_hash_.end()) return kNoId;
  for (int32_t r = it->second; r != kNoId; r = next_same_hash_[r]) {
    const std::span<const LinearTerm> other = terms_[r];
    if (rhs_[r] == rhs && std::equal(terms.begin(), terms.end(), other.begin(), other.end(),
                                     [](const LinearTerm& x, const LinearTerm& y) {
                                       return x.var == y.var && x.coef == y.coef;
                                     })) {
      return r;
    }
  }
  return kNoId;
}

int32_t InequalityRows::Add(std::span<const LinearTerm> terms, int64_t rhs, RowOrigin origin,
                            bool active, std::span<const int64_t> values) {
  const int32_t r = size();
  terms_.Append(terms);
  rhs_.push_back(rhs);
  origin_.push_back(origin);
  int64_t value = 0;
  for (const LinearTerm& t : terms) {
    value += t.coef * values[t.var];
    rows_of_bundle_[t.var].push_back({r, t.coef});
  }
  value_.push_back(value);
  active_.push_back(0);
  SetActive(r, active);
  const uint64_t h = Hash(terms, rhs);
  const auto [it, inserted] = first_with_hash_.try_emplace(h, r);
  next_same_hash_.push_back(inserted ? kNoId : it->second);
  if (!inserted) it->second = r;
  return r;
}

void InequalityRows::CountViolation(int32_t r, int sign) {
  if (active_[r] && value_[r] < rhs_[r]) num_violated_active_ += sign;
}

void InequalityRows::SetActive(int32_t r, bool active) {
  CountViolation(r, -1);
  active_[r] = active ? 1 : 0;
  CountViolation(r, +1);
}

void InequalityRows::OnBundleMoved(BundleId b, int64_t delta) {
  for (const Incidence& inc : rows_of_bundle_[b]) {
    CountViolation(inc.row, -1);
    value_[inc.row] += inc.coef * delta;
    CountViolation(inc.row, +1);
  }
}

}  // namespace ispq
