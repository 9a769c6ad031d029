// SPDX-License-Identifier: Apache-2.0
// Early-return helpers for absl::Status and absl::StatusOr, the idiom of Abseil-based code bases
// (Abseil's own macros are internal to it):
//
//   ISPQ_RETURN_IF_ERROR(Load(x));                       // returns the status if not ok
//   ISPQ_ASSIGN_OR_RETURN(TMesh mesh, TMeshFromProto(p));  // declares mesh, or returns
//
// Both evaluate their argument exactly once.
#ifndef ISPQ_CORE_STATUS_MACROS_H_
#define ISPQ_CORE_STATUS_MACROS_H_

#include <utility>

#include "absl/status/status.h"
#include "absl/status/statusor.h"

#define ISPQ_RETURN_IF_ERROR(expr)                                                     \
  do {                                                                                 \
    if (::absl::Status ispq_status_ = (expr); !ispq_status_.ok()) return ispq_status_; \
  } while (false)

#define ISPQ_STATUS_MACROS_CONCAT_INNER(x, y) x##y
#define ISPQ_STATUS_MACROS_CONCAT(x, y) ISPQ_STATUS_MACROS_CONCAT_INNER(x, y)

#define ISPQ_ASSIGN_OR_RETURN(lhs, expr) \
  ISPQ_ASSIGN_OR_RETURN_IMPL(ISPQ_STATUS_MACROS_CONCAT(ispq_statusor_, __LINE__), lhs, expr)

#define ISPQ_ASSIGN_OR_RETURN_IMPL(statusor, lhs, expr)    \
  auto statusor = (expr);                                  \
  if (!statusor.ok()) return std::move(statusor).status(); \
  lhs = *std::move(statusor)

#endif  // ISPQ_CORE_STATUS_MACROS_H_
