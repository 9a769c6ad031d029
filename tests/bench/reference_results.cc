// SPDX-License-Identifier: Apache-2.0
#include "tests/bench/reference_results.h"

#include <fstream>
#include <vector>

#include "absl/strings/str_split.h"

namespace ispq::bench {
namespace {

// Rows of a TSV file as maps from column name to value.
std::vector<std::map<std::string, std::string>> ReadTsv(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::map<std::string, std::string>> rows;
  std::string line;
  if (!std::getline(in, line)) return rows;
  const std::vector<std::string> header = absl::StrSplit(line, '\t');
  while (std::getline(in, line)) {
    const std::vector<std::string> fields = absl::StrSplit(line, '\t');
    std::map<std::string, std::string> row;
    for (size_t i = 0; i < header.size() && i < fields.size(); ++i) row[header[i]] = fields[i];
    rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace

ReferenceResults ReferenceResults::Load(const std::string& dir) {
  ReferenceResults results;
  for (const auto& row : ReadTsv(dir + "/qgp3d-isp.tsv")) {
    results.isp_[{row.at("dataset") + "/" + row.at("model"), std::stoi(row.at("percent"))}] = {
        std::stod(row.at("isp_wall_s")), std::stod(row.at("objective")), row.at("valid") == "yes"};
  }
  for (const auto& row : ReadTsv(dir + "/qgp3d-iqp-all.tsv")) {
    results.iqp_[{row.at("dataset") + "/" + row.at("model"), std::stoi(row.at("percent"))}] = {
        std::stod(row.at("iqp_wall_s")), std::stod(row.at("objective_at_limit")),
        row.at("valid") == "yes"};
  }
  return results;
}

std::optional<ReferenceRun> ReferenceResults::Isp(const std::string& model, int percent) const {
  const auto it = isp_.find({model, percent});
  if (it == isp_.end()) return std::nullopt;
  return it->second;
}

std::optional<ReferenceRun> ReferenceResults::Iqp(const std::string& model, int percent) const {
  const auto it = iqp_.find({model, percent});
  if (it == iqp_.end()) return std::nullopt;
  return it->second;
}

}  // namespace ispq::bench
