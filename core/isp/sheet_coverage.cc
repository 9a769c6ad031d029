// SPDX-License-Identifier: Apache-2.0
#include "core/isp/sheet_coverage.h"

namespace ispq {

SheetCoverage::SheetCoverage(int num_bundles)
    : generation_(2 * static_cast<size_t>(num_bundles), 0),
      sheet_index_(2 * static_cast<size_t>(num_bundles), -1) {}

void SheetCoverage::Cover(const IntegerSheet& sheet) {
  const int32_t id = static_cast<int32_t>(sheets_.size());
  sheets_.push_back(sheet.bundles);
  for (size_t i = 0; i < sheet.bundles.size(); ++i) {
    const size_t key = Key(sheet.bundles[i], sheet.deltas[i] > 0);
    generation_[key] = current_;
    sheet_index_[key] = id;
  }
}

void SheetCoverage::Clear() {
  ++current_;
  sheets_.clear();
}

std::optional<SheetCoverage::Answer> SheetCoverage::CoveringSheet(BundleId b, bool inflate) const {
  const size_t key = Key(b, inflate);
  if (generation_[key] != current_) return std::nullopt;
  const int32_t index = sheet_index_[key];
  return Answer{sheets_[index], (uint64_t{current_} << 32) | static_cast<uint32_t>(index)};
}

}  // namespace ispq
