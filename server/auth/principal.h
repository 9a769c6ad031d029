// SPDX-License-Identifier: Apache-2.0
// Who a call is made by. Every job and stored mesh belongs to the principal that created it and is
// visible only to that principal (its name in Job.owner and Mesh.owner) and to admin principals,
// which see and act on everything. Without authentication every caller is the same anonymous
// principal "", so everything is visible to everyone, as before principals existed.
#ifndef ISPQ_SERVER_AUTH_PRINCIPAL_H_
#define ISPQ_SERVER_AUTH_PRINCIPAL_H_

#include <string>
#include <string_view>

namespace ispq::server {

struct Principal {
  std::string name;
  bool admin = false;

  // Whether this principal may see and act on what `owner` created.
  bool CanAccess(std::string_view owner) const { return admin || owner == name; }
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_AUTH_PRINCIPAL_H_
