// SPDX-License-Identifier: Apache-2.0
// One request of the HTTP side and its answer, as the routes see them, apart from the library that
// carries them (server/http/http_server.h): the request is complete (its head checked, its body
// received within the bounds, its caller authenticated where the route needs one) before a route
// runs, and a route answers exactly once, possibly later and from another thread, through a
// Responder. A response's body is either held whole or produced as the client reads it
// (StreamedBody: server-sent events).
#ifndef ISPQ_SERVER_HTTP_HTTP_MESSAGE_H_
#define ISPQ_SERVER_HTTP_HTTP_MESSAGE_H_

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "absl/strings/string_view.h"
#include "server/auth/principal.h"
#include "server/memory/memory_budget.h"

namespace ispq::server::http {

using HttpFields = std::vector<std::pair<std::string, std::string>>;

struct HttpRequest {
  std::string method;   // "GET", "POST"...
  std::string path;     // without the query
  HttpFields headers;   // names in lower case, in the order received
  HttpFields query;     // decoded
  std::string peer;     // "ADDRESS:PORT"
  std::string id;       // what the route's {id} segment matched, if it has one
  Principal principal;  // the caller, on routes that authenticate
  std::string body;
  std::vector<MemoryReservation> body_memory;  // the body's share of the memory budget

  // The first header `name` (lower case), or "" when absent.
  absl::string_view Header(absl::string_view name) const;
  bool HasParam(absl::string_view name) const;
  // The first query parameter `name`, or "" when absent.
  absl::string_view Param(absl::string_view name) const;
  // Frees the body and its memory (a route that has converted it).
  void ReleaseBody();
};

// Whoever writes a StreamedBody to its client: lets it pause while it has nothing to write.
class StreamConnection {
 public:
  virtual ~StreamConnection() = default;
  // Stops asking the body for more until Resume. Only from inside StreamedBody::Produce.
  virtual void Suspend() = 0;
  // Asks the body again, soon. From any thread; only after Suspend, once per Suspend.
  virtual void Resume() = 0;
};

// A response body produced as the client reads it.
class StreamedBody {
 public:
  enum class Step {
    kMore,   // `out` holds the next bytes (or nothing, after Suspend): ask again
    kLast,   // `out` holds the last bytes: the body ends after them
    kAbort,  // end the connection without ending the body (the client should retry)
  };
  virtual ~StreamedBody() = default;
  // Appends the next bytes to the empty `out`. With nothing to write it calls
  // `connection.Suspend()` and arranges for `connection.Resume()` once it has something, then
  // returns kMore with `out` empty. Called on the server's thread, never concurrently.
  virtual Step Produce(std::string& out, StreamConnection& connection) = 0;
};

struct HttpResponse {
  int status = 200;
  std::string content_type;
  HttpFields headers;
  std::string body;
  absl::string_view static_body;         // instead of `body`: data that outlives the server
  MemoryReservation memory;              // the body's share of the memory budget, until it is sent
  std::unique_ptr<StreamedBody> stream;  // instead of either body: written as produced
};

// How a route answers, once, from any thread.
class Responder {
 public:
  virtual ~Responder() = default;
  virtual void Answer(HttpResponse response) = 0;
  // Whether an answer was given already (the route took too long, the server is stopping): the
  // route may stop working on it.
  virtual bool Answered() const = 0;
};

}  // namespace ispq::server::http

#endif  // ISPQ_SERVER_HTTP_HTTP_MESSAGE_H_
