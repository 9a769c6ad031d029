// SPDX-License-Identifier: Apache-2.0
#include "server/store/postgres/postgres_mesh_store.h"

#include <optional>
#include <utility>

#include "server/logging/log_value.h"
#include "server/model/resource_names.h"
#include "server/store/postgres/postgres_job_rows.h"
#include "spdlog/spdlog.h"

namespace ispq::server {

PostgresMeshStore::PostgresMeshStore(std::shared_ptr<PostgresConnections> connections, int capacity,
                                     int max_arcs)
    : connections_(std::move(connections)), capacity_(capacity), max_arcs_(max_arcs) {}

absl::StatusOr<std::shared_ptr<const StoredMesh>> PostgresMeshStore::Add(
    AdmittedMesh admitted, const MeshBytesSource& bytes, std::string owner, absl::Time now) {
  auto stored = std::make_shared<StoredMesh>();
  stored->id = NewResourceId();
  stored->owner = std::move(owner);
  stored->create_time = now;
  stored->admitted = std::move(admitted);
  const absl::Status status = connections_->Run([&](pqxx::connection& connection) {
    pqxx::work work(connection);
    work.exec_params(
        "INSERT INTO ispq_meshes (id, owner, stats, mesh, create_time_ns) "
        "VALUES ($1, $2, $3, $4, $5)",
        stored->id, stored->owner, ProtoBytes(stored->admitted.stats),
        pqxx::binarystring(bytes.Serialize()), absl::ToUnixNanos(now));
    work.exec_params(
        "DELETE FROM ispq_meshes WHERE id IN (SELECT id FROM ispq_meshes "
        "ORDER BY last_used DESC OFFSET $1)",
        capacity_);
    work.commit();
  });
  if (!status.ok()) return status;
  absl::MutexLock lock(&mutex_);
  decoded_[stored->id] = stored;
  return std::shared_ptr<const StoredMesh>(stored);
}

std::shared_ptr<const StoredMesh> PostgresMeshStore::Find(const std::string& id) {
  std::optional<v1::TMesh> proto;
  auto stored = std::make_shared<StoredMesh>();
  const absl::Status status = connections_->Run([&](pqxx::connection& connection) {
    proto.reset();
    pqxx::work work(connection);
    const pqxx::result rows = work.exec_params(
        "UPDATE ispq_meshes SET last_used = now() WHERE id = $1 "
        "RETURNING owner, create_time_ns, mesh",
        id);
    if (rows.empty()) return;
    stored->owner = rows[0][0].as<std::string>();
    stored->create_time = absl::FromUnixNanos(rows[0][1].as<int64_t>());
    const pqxx::binarystring bytes(rows[0][2]);
    proto.emplace();
    proto->ParseFromArray(bytes.data(), static_cast<int>(bytes.size()));
    work.commit();
  });
  if (!status.ok() || !proto.has_value()) return nullptr;
  {
    absl::MutexLock lock(&mutex_);
    if (auto it = decoded_.find(id); it != decoded_.end()) {
      if (std::shared_ptr<const StoredMesh> held = it->second.lock()) return held;
    }
  }
  absl::StatusOr<AdmittedMesh> admitted = AdmitMesh(*proto, max_arcs_);
  if (!admitted.ok()) {
    spdlog::error("event=stored_mesh_invalid mesh={} error={}", id,
                  QuotedLogValue(std::string(admitted.status().message())));
    return nullptr;
  }
  stored->id = id;
  stored->admitted = *std::move(admitted);
  absl::MutexLock lock(&mutex_);
  for (auto it = decoded_.begin(); it != decoded_.end();) {
    if (it->second.expired()) {
      decoded_.erase(it++);
    } else {
      ++it;
    }
  }
  decoded_[id] = stored;
  return stored;
}

bool PostgresMeshStore::Remove(const std::string& id) {
  bool removed = false;
  const absl::Status status = connections_->Run([&](pqxx::connection& connection) {
    pqxx::work work(connection);
    removed = !work.exec_params("DELETE FROM ispq_meshes WHERE id = $1 RETURNING id", id).empty();
    work.commit();
  });
  {
    absl::MutexLock lock(&mutex_);
    decoded_.erase(id);
  }
  return status.ok() && removed;
}

int PostgresMeshStore::size() const {
  int count = 0;
  const absl::Status status = connections_->Run([&](pqxx::connection& connection) {
    pqxx::work work(connection);
    count = work.exec("SELECT count(*) FROM ispq_meshes")[0][0].as<int>();
  });
  return status.ok() ? count : -1;
}

}  // namespace ispq::server
