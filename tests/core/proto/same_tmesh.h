// SPDX-License-Identifier: Apache-2.0
// Whether two decodings of one T-mesh gave the same model: the element counts, the critical
// entities, the bundles and subproblems, and every arc's nodes, length and criticality. Tests of
// the decoders (whole message, element by element, from a file) compare through this.
#ifndef ISPQ_TESTS_CORE_PROTO_SAME_TMESH_H_
#define ISPQ_TESTS_CORE_PROTO_SAME_TMESH_H_

#include "core/tmesh.h"

namespace ispq::testing {

// Records a GoogleTest failure for the first difference.
void ExpectSameTMesh(const TMesh& a, const TMesh& b);

}  // namespace ispq::testing

#endif  // ISPQ_TESTS_CORE_PROTO_SAME_TMESH_H_
