#!/usr/bin/env bash
# Validates docker/docker-compose.yml with Debian's docker-compose (no Docker engine needed) and
# checks what the deployment promises: the server with a health check through the gRPC health
# service and a data volume, and a Prometheus whose configuration scrapes it.
#   compose_config_test.sh REPOSITORY_ROOT
set -euo pipefail
root=$1
config=$(docker-compose -f "$root/docker/docker-compose.yml" config)
fail() { echo "compose: $*" >&2; exit 1; }
grep -q 'dockerfile: docker/Dockerfile' <<<"$config" || fail "mesh4d is not built from docker/Dockerfile"
grep -q 'mesh4d-client' <<<"$config" || fail "no health check through mesh4d-client"
grep -q '/var/lib/mesh4d' <<<"$config" || fail "no data volume"
grep -q 'dockerfile: prometheus.Dockerfile' <<<"$config" || fail "no Prometheus service from Debian's package"
grep -q 'mesh4d:9464' "$root/docker/prometheus.yml" || fail "Prometheus does not scrape mesh4d:9464"
grep -q '^USER mesh4d' "$root/docker/Dockerfile" || fail "the image does not run as a non-root user"
grep -q '^HEALTHCHECK' "$root/docker/Dockerfile" || fail "the image has no HEALTHCHECK"
echo "docker-compose.yml valid; server, health check, volume and Prometheus present"
