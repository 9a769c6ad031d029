// SPDX-License-Identifier: Apache-2.0
#include "server/http/mhd_callbacks.h"

#include "server/http/connection_deadlines.h"
#include "server/http/mhd_request.h"
#include "server/http/request_dispatcher.h"

namespace ispq::server::http {

MHD_Result OnMhdRequest(void* dispatcher, MHD_Connection* connection, const char* url,
                        const char* method, const char* /*version*/, const char* upload_data,
                        size_t* upload_data_size, void** context) {
  return static_cast<RequestDispatcher*>(dispatcher)
      ->Handle(connection, url, method, upload_data, upload_data_size, context);
}

void OnMhdRequestCompleted(void* dispatcher, MHD_Connection* connection, void** context,
                           MHD_RequestTerminationCode /*why*/) {
  static_cast<RequestDispatcher*>(dispatcher)->Completed(connection, context);
}

void OnMhdConnection(void* deadlines, MHD_Connection* connection, void** /*socket_context*/,
                     MHD_ConnectionNotificationCode code) {
  auto* const watched = static_cast<ConnectionDeadlines*>(deadlines);
  if (code == MHD_CONNECTION_NOTIFY_STARTED) {
    watched->Opened(connection, SocketOf(connection));
  } else {
    watched->Closed(connection);
  }
}

}  // namespace ispq::server::http
