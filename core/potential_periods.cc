// SPDX-License-Identifier: Apache-2.0
#include "core/potential_periods.h"

#include <cstdlib>
#include <functional>
#include <numeric>
#include <queue>
#include <utility>

#include "core/disjoint_sets.h"
#include "core/linear_terms.h"
#include "core/tmesh.h"

namespace ispq {
namespace {

// Resolving rows takes a pass per link of the longest chain of implications; what is still open
// after this many passes is eliminated instead.
constexpr int kMaxPasses = 64;
// Eliminating rows substitutes expressions into each other; coefficients past this give up.
constexpr int64_t kMaxCoefficient = int64_t{1} << 20;

// Union-find over bundle values with signs: value(x) = sign * value(root), and a root may be
// known to be zero.
class SignedClasses {
 public:
  explicit SignedClasses(int32_t n) : parent_(n), sign_(n, 1), zero_(n, 0) {
    std::iota(parent_.begin(), parent_.end(), 0);
  }

  // x's root and the sign of x relative to it.
  std::pair<int32_t, int8_t> Find(int32_t x) {
    int32_t root = x;
    int8_t sign = 1;
    while (parent_[root] != root) {
      sign = static_cast<int8_t>(sign * sign_[root]);
      root = parent_[root];
    }
    // Hang the path from the root.
    int8_t sy = sign;
    for (int32_t y = x; y != root && parent_[y] != root;) {
      const int32_t next = parent_[y];
      const int8_t snext = static_cast<int8_t>(sy * sign_[y]);
      parent_[y] = root;
      sign_[y] = sy;
      y = next;
      sy = snext;
    }
    return {root, sign};
  }
  bool zero(int32_t root) const { return zero_[root] != 0; }
  void SetZero(int32_t root) { zero_[root] = 1; }
  // value(a) = relation * value(b), for roots a and b.
  void Join(int32_t a, int32_t b, int8_t relation) {
    if (a == b) {
      if (relation < 0) zero_[a] = 1;  // x = -x
      return;
    }
    parent_[a] = b;
    sign_[a] = relation;
    if (zero_[a]) zero_[b] = 1;
  }

 private:
  std::vector<int32_t> parent_;
  std::vector<int8_t> sign_;
  std::vector<uint8_t> zero_;
};

// The rows over the bundles off the forest, flat.
struct OffForestRows {
  std::vector<int64_t> begin{0};
  std::vector<LinearTerm> terms;
  int num_rows() const { return static_cast<int>(begin.size()) - 1; }
};

// Per bundle: whether it is an edge of a spanning forest of the potentials (bundles in order);
// the others are where the periods live.
std::vector<uint8_t> SpanningForest(int32_t num_potentials, std::span<const int32_t> tail,
                                    std::span<const int32_t> head) {
  std::vector<uint8_t> on_forest(tail.size(), 0);
  DisjointSets forest(num_potentials);
  for (size_t b = 0; b < tail.size(); ++b) {
    if (forest.Find(tail[b]) == forest.Find(head[b])) continue;
    forest.Join(tail[b], head[b]);
    on_forest[b] = 1;
  }
  return on_forest;
}

// The consistency rows over bundles, without the forest's; rows left empty are dropped.
OffForestRows RowsOffForest(const ConsistencyMatrix& consistency, const ArcBundles& bundles,
                            std::span<const uint8_t> on_forest) {
  OffForestRows rows;
  for (int r = 0; r < consistency.num_rows(); ++r) {
    const size_t begin = rows.terms.size();
    for (const LinearTerm& t : consistency.row(r)) {
      const BundleId b = bundles.bundle_of(t.var);
      if (!on_forest[b]) rows.terms.push_back({b, t.coef});
    }
    MergeRepeatedTerms(rows.terms, begin);
    if (rows.terms.size() > begin) rows.begin.push_back(static_cast<int64_t>(rows.terms.size()));
  }
  return rows;
}

// The row over the classes not known to be zero.
void FreeTerms(const OffForestRows& rows, int r, SignedClasses& classes,
               std::vector<LinearTerm>* free_terms) {
  free_terms->clear();
  for (int64_t k = rows.begin[r]; k < rows.begin[r + 1]; ++k) {
    const auto [root, sign] = classes.Find(rows.terms[k].var);
    if (!classes.zero(root)) free_terms->push_back({root, sign * rows.terms[k].coef});
  }
  MergeRepeatedTerms(*free_terms);
}

// Resolves the rows of one or two terms into the classes, pass after pass; marks them resolved.
void ResolveShortRows(const OffForestRows& rows, SignedClasses& classes,
                      std::vector<uint8_t>& resolved) {
  std::vector<LinearTerm> free_terms;
  bool changed = true;
  for (int pass = 0; changed && pass < kMaxPasses; ++pass) {
    changed = false;
    for (int r = 0; r < rows.num_rows(); ++r) {
      if (resolved[r]) continue;
      FreeTerms(rows, r, classes, &free_terms);
      if (free_terms.size() == 1) {
        classes.SetZero(free_terms[0].var);
      } else if (free_terms.size() == 2 &&
                 std::abs(free_terms[0].coef) == std::abs(free_terms[1].coef)) {
        const bool same_sign = (free_terms[0].coef > 0) == (free_terms[1].coef > 0);
        classes.Join(free_terms[0].var, free_terms[1].var, same_sign ? -1 : 1);
      } else if (!free_terms.empty()) {
        continue;
      }
      resolved[r] = 1;
      changed = changed || !free_terms.empty();
    }
  }
}

// Gaussian elimination of the rows still open, over class roots, the shortest row first: each
// makes one of its terms with coefficient +-1 a pivot, the one in fewest other rows and
// expressions, an integer combination of the row's other terms, and is substituted at once into
// every row and expression that holds it (so that expressions only ever hold free roots, and
// fill-in stays where the rows are, around each handle). false if a row has no such term or a
// coefficient grows past kMaxCoefficient.
class OpenRowElimination {
 public:
  OpenRowElimination(int32_t num_roots, std::vector<uint8_t>* is_pivot,
                     std::vector<std::vector<LinearTerm>>* expression)
      : users_(num_roots), is_pivot_(*is_pivot), expression_(*expression) {}

  bool Run(std::vector<std::vector<LinearTerm>> rows) {
    rows_ = std::move(rows);
    using Entry = std::pair<size_t, int32_t>;  // (length, row)
    std::priority_queue<Entry, std::vector<Entry>, std::greater<>> shortest;
    for (int32_t r = 0; r < static_cast<int32_t>(rows_.size()); ++r) {
      for (const LinearTerm& t : rows_[r]) users_[t.var].push_back(RowUser(r));
      shortest.push({rows_[r].size(), r});
    }
    std::vector<uint8_t> done(rows_.size(), 0);
    while (!shortest.empty()) {
      const auto [length, r] = shortest.top();
      shortest.pop();
      if (done[r] || length != rows_[r].size()) continue;  // stale: pushed again
      done[r] = 1;
      if (rows_[r].empty()) continue;
      int32_t p = kNoId;
      int32_t cp = 0;
      for (const LinearTerm& t : rows_[r]) {
        if (std::abs(t.coef) == 1 && (p == kNoId || users_[t.var].size() < users_[p].size())) {
          p = t.var;
          cp = t.coef;
        }
      }
      if (p == kNoId) return false;
      // cp x_p + sum c_j x_j = 0, cp = +-1: x_p = sum -cp c_j x_j.
      std::vector<LinearTerm> e;
      for (const LinearTerm& t : rows_[r]) {
        if (t.var != p) e.push_back({t.var, -cp * t.coef});
      }
      is_pivot_[p] = 1;
      std::vector<int32_t> users = std::move(users_[p]);
      users_[p].clear();
      for (const int32_t user : users) {
        std::vector<LinearTerm>& terms = IsRow(user) ? rows_[RowOf(user)] : expression_[user];
        if (!Substitute(p, e, user, terms)) return false;
        if (IsRow(user) && !done[RowOf(user)]) shortest.push({terms.size(), RowOf(user)});
      }
      for (const LinearTerm& t : e) users_[t.var].push_back(p);
      expression_[p] = std::move(e);
    }
    return true;
  }

 private:
  // A user of a root is a row (encoded negative) or a pivot whose expression holds it.
  static int32_t RowUser(int32_t r) { return -1 - r; }
  static bool IsRow(int32_t user) { return user < 0; }
  static int32_t RowOf(int32_t user) { return -1 - user; }

  // Replaces x_p in `terms` (of `user`) by `e`; the new roots get `user` as a user.
  bool Substitute(int32_t p, const std::vector<LinearTerm>& e, int32_t user,
                  std::vector<LinearTerm>& terms) {
    int64_t scale = 0;
    size_t kept = 0;
    for (const LinearTerm& t : terms) {
      if (t.var == p) {
        scale = t.coef;
      } else {
        terms[kept++] = t;
      }
    }
    terms.resize(kept);
    if (scale == 0) return true;  // a stale use: substituted away before
    for (const LinearTerm& u : e) {
      const int64_t coef = scale * u.coef;
      if (std::abs(coef) > kMaxCoefficient) return false;
      terms.push_back({u.var, static_cast<int32_t>(coef)});
      users_[u.var].push_back(user);
    }
    MergeRepeatedTerms(terms);
    for (const LinearTerm& t : terms) {
      if (std::abs(t.coef) > kMaxCoefficient) return false;
    }
    return true;
  }

  std::vector<std::vector<LinearTerm>> rows_;
  std::vector<std::vector<int32_t>> users_;  // per root: rows and expressions that may hold it
  std::vector<uint8_t>& is_pivot_;
  std::vector<std::vector<LinearTerm>>& expression_;
};

}  // namespace

std::optional<PotentialPeriods> FindPotentialPeriods(int32_t num_potentials,
                                                     std::span<const int32_t> tail,
                                                     std::span<const int32_t> head,
                                                     const ConsistencyMatrix& consistency,
                                                     const ArcBundles& bundles) {
  const int32_t num_bundles = bundles.num_bundles();
  const std::vector<uint8_t> on_forest = SpanningForest(num_potentials, tail, head);
  const OffForestRows rows = RowsOffForest(consistency, bundles, on_forest);
  SignedClasses classes(num_bundles);
  std::vector<uint8_t> resolved(rows.num_rows(), 0);
  ResolveShortRows(rows, classes, resolved);
  std::vector<std::vector<LinearTerm>> open_rows;
  std::vector<LinearTerm> free_terms;
  for (int r = 0; r < rows.num_rows(); ++r) {
    if (resolved[r]) continue;
    FreeTerms(rows, r, classes, &free_terms);
    if (!free_terms.empty()) open_rows.push_back(free_terms);
  }
  std::vector<uint8_t> is_pivot(num_bundles, 0);
  std::vector<std::vector<LinearTerm>> expression(num_bundles);
  if (!OpenRowElimination(num_bundles, &is_pivot, &expression).Run(std::move(open_rows))) {
    return std::nullopt;
  }

  PotentialPeriods periods;
  std::vector<int32_t> period_of_root(num_bundles, kNoId);
  const auto period = [&](int32_t root) {
    if (period_of_root[root] == kNoId) period_of_root[root] = periods.num_periods++;
    return period_of_root[root];
  };
  std::vector<LinearTerm> terms;
  for (BundleId b = 0; b < num_bundles; ++b) {
    terms.clear();
    if (!on_forest[b]) {
      const auto [root, sign] = classes.Find(b);
      if (is_pivot[root]) {
        for (const LinearTerm& t : expression[root]) {
          terms.push_back({period(t.var), sign * t.coef});
        }
      } else if (!classes.zero(root)) {
        terms.push_back({period(root), sign});
      }
    }
    periods.terms.Append(terms);
  }
  return periods;
}

}  // namespace ispq
