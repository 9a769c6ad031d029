// SPDX-License-Identifier: Apache-2.0
// Resource names of the service (AIP-122): jobs are "jobs/{id}", stored meshes "meshes/{id}".
//
// Ids are 16 random lowercase hex digits, so that names are not guessable from one another and
// are not reused while a server runs. Parsing accepts any AIP-122 style id (lowercase letters,
// digits and '-', at most 63 characters) and leaves existence to the stores, so a well-formed
// name that was never issued is NOT_FOUND while a malformed one is INVALID_ARGUMENT.
#ifndef ISPQ_SERVER_MODEL_RESOURCE_NAMES_H_
#define ISPQ_SERVER_MODEL_RESOURCE_NAMES_H_

#include <string>

#include "absl/status/statusor.h"

namespace ispq::server {

inline constexpr char kJobCollection[] = "jobs";
inline constexpr char kMeshCollection[] = "meshes";

// A fresh random id. Thread-safe.
std::string NewResourceId();

// "<collection>/<id>".
std::string ResourceName(const char* collection, const std::string& id);

// The id of `name` if it is "<collection>/<id>" with a well-formed id; INVALID_ARGUMENT naming
// the expected form otherwise (a hostile name is quoted only in part).
absl::StatusOr<std::string> ParseResourceName(const char* collection, const std::string& name);

}  // namespace ispq::server

#endif  // ISPQ_SERVER_MODEL_RESOURCE_NAMES_H_
