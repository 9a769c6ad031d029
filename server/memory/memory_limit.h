// SPDX-License-Identifier: Apache-2.0
// How large the memory budget is (server/memory/memory_budget.h): the --max_memory_bytes flag,
// which takes sizes such as "512MiB", and its default, derived from the memory the process may use.
//
// The default is three quarters of the container's limit (cgroup v2 memory.max or cgroup v1
// memory.limit_in_bytes of the process's own cgroup, or of its ancestors) when there is one, else
// half of the physical memory: the rest covers what the budget does not account (the process's
// base, allocator slack, the solver's peaks above the estimate).
#ifndef ISPQ_SERVER_MEMORY_MEMORY_LIMIT_H_
#define ISPQ_SERVER_MEMORY_MEMORY_LIMIT_H_

#include <cstdint>
#include <optional>

#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"

namespace ispq::server {

// "536870912", "512MiB", "2GiB", "64KiB", "1.5GiB" (binary units; "MB"/"GB" are read as decimal
// units). INVALID_ARGUMENT for anything else, zero or negative.
absl::StatusOr<int64_t> ParseByteSize(absl::string_view text);

// The memory limit of the process's cgroup, if it has one (not "max" or unlimited).
std::optional<int64_t> CgroupMemoryLimit();

// The default budget as described above.
int64_t DefaultMemoryBudget();

}  // namespace ispq::server

#endif  // ISPQ_SERVER_MEMORY_MEMORY_LIMIT_H_
