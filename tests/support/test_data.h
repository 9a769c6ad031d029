// Locating and loading the T-meshes tests run on: the real shared set (../shared/data/tmesh,
// required: a missing set fails the tests instead of skipping them) and the samples bundled in
// tests/data.
#ifndef ISPQ_TESTS_SUPPORT_TEST_DATA_H_
#define ISPQ_TESTS_SUPPORT_TEST_DATA_H_

#include <string>
#include <vector>

#include "core/tmesh.h"
#include "ispq/v1/tmesh.pb.h"

namespace ispq::testing {

// Every *.tmesh.json under the shared data directory, sorted. Empty if the directory is missing
// (callers assert non-emptiness so that a missing data set fails loudly).
std::vector<std::string> SharedTMeshFiles();
std::string SharedTMeshDir();

// A file bundled with the repository, e.g. BundledSample("s01c_cube.tmesh.json").
std::string BundledSample(const std::string& file_name);

// Short name of a shared file: "<dataset>/<model>".
std::string ShortName(const std::string& path);

// Parses and validates; aborts the test binary with the error on failure (test inputs are
// expected to be valid).
v1::TMesh LoadProtoOrDie(const std::string& path);
TMesh LoadTMeshOrDie(const std::string& path);
TMesh TMeshOrDie(const v1::TMesh& proto);

}  // namespace ispq::testing

#endif  // ISPQ_TESTS_SUPPORT_TEST_DATA_H_
