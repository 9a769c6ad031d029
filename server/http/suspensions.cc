// SPDX-License-Identifier: Apache-2.0
#include "server/http/suspensions.h"

#include <microhttpd.h>

namespace ispq::server::http {

void Suspensions::Suspend(MHD_Connection* connection) {
  ++suspended_;
  MHD_suspend_connection(connection);
}

void Suspensions::Resume(MHD_Connection* connection) {
  MHD_resume_connection(connection);
  --suspended_;
}

}  // namespace ispq::server::http
