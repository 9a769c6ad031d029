// SPDX-License-Identifier: Apache-2.0
// Locating and loading the T-meshes tests run on: the 62 real T-meshes bundled in
// tests/data/tmesh (tests/data/tmesh/README.md: provenance, licence), required (a missing or
// partial set fails the tests instead of skipping them), and upstream's results on them in
// tests/data/reference. The build bakes in both folders of the source tree; nothing outside the
// checkout is read.
#ifndef ISPQ_TESTS_SUPPORT_TEST_DATA_H_
#define ISPQ_TESTS_SUPPORT_TEST_DATA_H_

#include <string>
#include <vector>

#include "core/tmesh.h"
#include "ispq/v1/tmesh.pb.h"

namespace ispq::testing {

// Every *.tmesh.json under the real set's folder, sorted. Empty if the folder is missing
// (callers assert non-emptiness so that a missing data set fails loudly).
std::vector<std::string> RealTMeshFiles();
std::string RealTMeshDir();

// One file of the real set by "<dataset>/<file>", e.g.
// RealTMeshPath("hex-me/s01c_cube.tmesh.json").
std::string RealTMeshPath(const std::string& dataset_and_file);

// The folder of upstream's reference results (qgp3d-isp.tsv, qgp3d-iqp-all.tsv).
std::string ReferenceResultsDir();

// Short name of a real file: "<dataset>/<model>".
std::string ShortName(const std::string& path);

// Parses and validates; aborts the test binary with the error on failure (test inputs are
// expected to be valid).
v1::TMesh LoadProtoOrDie(const std::string& path);
TMesh LoadTMeshOrDie(const std::string& path);
TMesh TMeshOrDie(const v1::TMesh& proto);

}  // namespace ispq::testing

#endif  // ISPQ_TESTS_SUPPORT_TEST_DATA_H_
