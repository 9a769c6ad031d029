#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# What the official postgres image's entrypoint does, for what components/postgres uses: on an
# empty $PGDATA, initdb with $POSTGRES_USER as the superuser (password $POSTGRES_PASSWORD,
# scram-sha-256 over TCP) and create $POSTGRES_DB; then run postgres listening on every address.
# Arguments starting with "-" are postgres's (e.g. `-c max_connections=200`).
set -euo pipefail
if [ "${1:-}" != "" ] && [ "${1:0:1}" = "-" ]; then set -- postgres "$@"; fi
if [ "${1:-}" != "postgres" ]; then exec "$@"; fi
shift
: "${POSTGRES_USER:=postgres}" "${POSTGRES_DB:=$POSTGRES_USER}"
if [ -z "${POSTGRES_PASSWORD:-}" ]; then
  echo "postgres-entrypoint: POSTGRES_PASSWORD is not set" >&2
  exit 1
fi
if [ ! -s "$PGDATA/PG_VERSION" ]; then
  mkdir -p "$PGDATA"
  chmod 0700 "$PGDATA"
  initdb --username="$POSTGRES_USER" --pwfile=<(printf '%s\n' "$POSTGRES_PASSWORD") \
    --auth-local=trust --auth-host=scram-sha-256 -D "$PGDATA" >/dev/null
  echo "host all all all scram-sha-256" >>"$PGDATA/pg_hba.conf"
  echo "CREATE DATABASE \"$POSTGRES_DB\";" |
    postgres --single -j -D "$PGDATA" postgres >/dev/null
  echo "postgres-entrypoint: initialized $PGDATA with database $POSTGRES_DB"
fi
exec postgres -D "$PGDATA" -c listen_addresses='*' "$@"
