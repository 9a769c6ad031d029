// SPDX-License-Identifier: Apache-2.0
// The functions libmicrohttpd calls on its event threads, handing each call to the object the
// daemon was started with: requests and their completion to the RequestDispatcher
// (server/http/request_dispatcher.h), connections opening and closing to ConnectionDeadlines
// (server/http/connection_deadlines.h). HttpServer installs them, and so do the tests that run a
// dispatcher on a daemon of their own, so that both wire libmicrohttpd the same way.
#ifndef ISPQ_SERVER_HTTP_MHD_CALLBACKS_H_
#define ISPQ_SERVER_HTTP_MHD_CALLBACKS_H_

#include <microhttpd.h>

#include <cstddef>

namespace ispq::server::http {

// MHD_AccessHandlerCallback; `dispatcher` is the RequestDispatcher.
MHD_Result OnMhdRequest(void* dispatcher, MHD_Connection* connection, const char* url,
                        const char* method, const char* version, const char* upload_data,
                        size_t* upload_data_size, void** context);
// MHD_OPTION_NOTIFY_COMPLETED; `dispatcher` is the RequestDispatcher.
void OnMhdRequestCompleted(void* dispatcher, MHD_Connection* connection, void** context,
                           MHD_RequestTerminationCode why);
// MHD_OPTION_NOTIFY_CONNECTION; `deadlines` is the ConnectionDeadlines.
void OnMhdConnection(void* deadlines, MHD_Connection* connection, void** socket_context,
                     MHD_ConnectionNotificationCode code);

}  // namespace ispq::server::http

#endif  // ISPQ_SERVER_HTTP_MHD_CALLBACKS_H_
