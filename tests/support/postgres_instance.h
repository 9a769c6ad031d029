// A real PostgreSQL server for tests, from Debian's `postgresql` package: a fresh cluster
// (initdb) in a temporary directory, started with pg_ctl on a free loopback port, trust
// authentication for the one test user, fsync off. As root (CI) the cluster runs as the
// package's unprivileged `postgres` user, since PostgreSQL refuses to run as root. Start is
// bounded in time; the destructor stops the server (immediate mode) and removes the directory.
#ifndef ISPQ_TESTS_SUPPORT_POSTGRES_INSTANCE_H_
#define ISPQ_TESTS_SUPPORT_POSTGRES_INSTANCE_H_

#include <memory>
#include <string>

#include "absl/status/statusor.h"

namespace ispq::testing {

class PostgresInstance {
 public:
  // Fails with the commands' output if PostgreSQL is not installed or does not start.
  static absl::StatusOr<std::unique_ptr<PostgresInstance>> Start();
  ~PostgresInstance();
  PostgresInstance(const PostgresInstance&) = delete;
  PostgresInstance& operator=(const PostgresInstance&) = delete;

  // postgresql://ispq@127.0.0.1:<port>/<database>
  std::string uri(const std::string& database = "postgres") const;
  // A new empty database, for a test that needs a store of its own.
  absl::StatusOr<std::string> CreateDatabase(const std::string& name);
  // Runs one SQL command with psql; its output.
  absl::StatusOr<std::string> Sql(const std::string& sql, const std::string& database = "postgres");

 private:
  PostgresInstance() = default;

  std::string directory_;
  std::string bin_;
  std::string as_user_;  // a command prefix that runs as the cluster's owner, or empty
  int port_ = 0;
  bool started_ = false;
};

}  // namespace ispq::testing

#endif  // ISPQ_TESTS_SUPPORT_POSTGRES_INSTANCE_H_
