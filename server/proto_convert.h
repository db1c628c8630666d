// Conversions between the engine's types and the mesh4d.v1 messages.
#pragma once

#include "mesh/mesh_stats.h"
#include "mesh4d/v1/mesh4d.pb.h"
#include "refine/fidelity_certificate.h"
#include "refine/progress.h"
#include "refine/refine_params.h"

namespace mesh4d::server {

/// The request's parameters with the engine's defaults where a field is 0 (unset).
refine::RefineParams to_engine(const v1::RefineParams& p);
/// Whether the request asks for periodic time; throws wire::ServiceError (INVALID_ARGUMENT)
/// for a time_topology this server does not know.
bool periodic_time(const v1::RefineParams& p);
/// Every field filled in (what the job record shows).
v1::RefineParams to_proto(const refine::RefineParams& p, unsigned threads);

v1::MeshStats to_proto(const mesh::MeshStats& s);
/// Appends the certificate's labels to `stats`.
void add_certificate(const refine::FidelityCertificate& c, v1::MeshStats* stats);
v1::Progress to_proto(const refine::Progress& p);
v1::Phase to_proto(refine::Phase phase);

}  // namespace mesh4d::server
