// SPDX-License-Identifier: Apache-2.0
// A T-mesh made of several disjoint copies of a real one, for jobs whose length a test controls.
//
// Tests of cancellation, deadlines, full queues and shutdown need a job that is still running
// when the test acts, on any machine and however fast the quantizer becomes. Quantizing k
// disjoint copies of a real mesh takes about k times as long as one copy (the components are
// independent subproblems solved one after another), so a test measures one copy in-process
// and picks k for the duration it needs. The copies are real data: every id is offset into its
// copy's range, so the result is a valid T-mesh of k components.
#ifndef ISPQ_TESTS_SUPPORT_TMESH_COPIES_H_
#define ISPQ_TESTS_SUPPORT_TMESH_COPIES_H_

#include "ispq/v1/tmesh.pb.h"

namespace ispq::testing {

// `copies` >= 1 disjoint copies of `mesh`, named "<name>x<copies>". Levels, exporter stats and
// the critical entity list are dropped (the loader derives the entities, in the format's order
// of nodes, links and regions across all copies; levels are recomputed when requested).
v1::TMesh DisjointCopies(const v1::TMesh& mesh, int copies);

}  // namespace ispq::testing

#endif  // ISPQ_TESTS_SUPPORT_TMESH_COPIES_H_
