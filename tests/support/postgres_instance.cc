#include "tests/support/postgres_instance.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "tests/support/run_command.h"

namespace ispq::testing {
namespace {

// A port nobody listens on right now (the kernel's pick for port 0).
int FreeLoopbackPort() {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  address.sin_port = 0;
  socklen_t length = sizeof(address);
  int port = 0;
  if (bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof(address)) == 0 &&
      getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length) == 0) {
    port = ntohs(address.sin_port);
  }
  close(fd);
  return port;
}

// The newest installed PostgreSQL's bin directory, e.g. /usr/lib/postgresql/15/bin.
std::string PostgresBinDirectory() {
  const CommandResult found =
      RunCommand("ls -d /usr/lib/postgresql/*/bin 2>/dev/null | sort -V | tail -n 1");
  std::string bin = found.output;
  while (!bin.empty() && (bin.back() == '\n' || bin.back() == ' ')) bin.pop_back();
  return bin;
}

}  // namespace

absl::StatusOr<std::unique_ptr<PostgresInstance>> PostgresInstance::Start() {
  std::unique_ptr<PostgresInstance> instance(new PostgresInstance());
  instance->bin_ = PostgresBinDirectory();
  if (instance->bin_.empty()) {
    return absl::FailedPreconditionError(
        "PostgreSQL is not installed: run deploy/install-deps.sh (package postgresql)");
  }
  char pattern[] = "/tmp/ispq-postgres-XXXXXX";
  if (mkdtemp(pattern) == nullptr) return absl::InternalError("mkdtemp failed");
  instance->directory_ = pattern;
  if (geteuid() == 0) {
    // PostgreSQL refuses to run as root: the package's own unprivileged user owns the cluster.
    instance->as_user_ = "runuser -u postgres -- ";
    RunCommand(absl::StrCat("chown postgres: ", instance->directory_));
  }
  instance->port_ = FreeLoopbackPort();
  const std::string& dir = instance->directory_;
  const CommandResult init =
      RunCommand(absl::StrCat("timeout 60 ", instance->as_user_, instance->bin_, "/initdb -D ", dir,
                              "/data -U ispq --auth=trust --no-sync -E UTF8 --locale=C.UTF-8"));
  if (init.exit_code != 0) {
    return absl::InternalError(absl::StrCat("initdb failed:\n", init.output));
  }
  const CommandResult start = RunCommand(
      absl::StrCat("timeout 60 ", instance->as_user_, instance->bin_, "/pg_ctl -D ", dir,
                   "/data -l ", dir, "/log -w -t 30 -o \"-p ", instance->port_, " -k ", dir,
                   " -c listen_addresses=127.0.0.1 -c fsync=off -c synchronous_commit=off "
                   "-c full_page_writes=off -c max_connections=300\" start"));
  if (start.exit_code != 0) {
    const CommandResult log = RunCommand(absl::StrCat("cat ", dir, "/log"));
    return absl::InternalError(
        absl::StrCat("pg_ctl start failed:\n", start.output, "\nserver log:\n", log.output));
  }
  instance->started_ = true;
  return instance;
}

PostgresInstance::~PostgresInstance() {
  if (started_) {
    RunCommand(absl::StrCat("timeout 30 ", as_user_, bin_, "/pg_ctl -D ", directory_,
                            "/data -m immediate -w -t 20 stop"));
  }
  if (!directory_.empty()) {
    std::error_code ignored;
    std::filesystem::remove_all(directory_, ignored);
  }
}

std::string PostgresInstance::uri(const std::string& database) const {
  return absl::StrCat("postgresql://ispq@127.0.0.1:", port_, "/", database);
}

absl::StatusOr<std::string> PostgresInstance::Sql(const std::string& sql,
                                                  const std::string& database) {
  const CommandResult result =
      RunCommand(absl::StrCat("timeout 30 ", bin_, "/psql -X -q -t -A -v ON_ERROR_STOP=1 '",
                              uri(database), "' -c \"", sql, "\""));
  if (result.exit_code != 0) {
    return absl::InternalError(absl::StrCat("psql failed: ", sql, "\n", result.output));
  }
  return result.output;
}

absl::StatusOr<std::string> PostgresInstance::CreateDatabase(const std::string& name) {
  absl::StatusOr<std::string> created = Sql(absl::StrCat("CREATE DATABASE ", name));
  if (!created.ok()) return created.status();
  return uri(name);
}

}  // namespace ispq::testing
