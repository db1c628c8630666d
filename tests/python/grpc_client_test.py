#!/usr/bin/python3
"""A foreign client, the way a hospital pipeline script would drive mesh4d: Debian's
python3-grpcio with stubs generated here from our .proto files (protoc + grpc_python_plugin),
against the real mesh4d-server on a loopback port. It submits a small 4D hypersphere, watches
the job to the end, fetches the mesh and checks it against the documented .m4d layout.

Usage: grpc_client_test.py PATH/TO/mesh4d-server PATH/TO/proto
"""
import hashlib
import os
import signal
import struct
import subprocess
import sys
import tempfile

import numpy
from mesh4d_server import start_server

PROTOC = "/usr/bin/protoc"
GRPC_PYTHON_PLUGIN = "/usr/bin/grpc_python_plugin"


def generate_stubs(proto_dir, out_dir):
    """Python modules for our API and the standard health service, from the .proto files."""
    os.makedirs(out_dir, exist_ok=True)
    # The health stubs go in at the top level: a "grpc" folder would hide the grpcio package.
    for include, proto in ((proto_dir, "mesh4d/v1/mesh4d.proto"),
                           (os.path.join(proto_dir, "grpc/health/v1"), "health.proto")):
        subprocess.run([PROTOC, "-I", include, f"--python_out={out_dir}",
                        f"--grpc_python_out={out_dir}",
                        f"--plugin=protoc-gen-grpc_python={GRPC_PYTHON_PLUGIN}",
                        os.path.join(include, proto)], check=True)
    sys.path.insert(0, out_dir)


def hypersphere(n, radius):
    """uint8 labels, 1 inside a 4-ball centred in an n^4 image; x fastest like the API wants."""
    axis = numpy.arange(n) - (n - 1) / 2
    x, y, z, t = numpy.meshgrid(axis, axis, axis, axis, indexing="ij")
    inside = x * x + y * y + z * z + t * t <= radius * radius
    return inside.astype(numpy.uint8).tobytes(order="F")


def submit_requests(pb, data, request_id, dims):
    header = pb.ImageHeader(
        dims=pb.Size4(x=dims, y=dims, z=dims, t=dims),
        spacing=pb.Vec4(x=1, y=1, z=1, t=1), origin=pb.Vec4(),
        label_type=pb.LABEL_TYPE_UINT8, byte_size=len(data),
        sha256=hashlib.sha256(data).digest())
    spec = pb.JobSpec(image=header, params=pb.RefineParams(delta=3, seed=7),
                      request_id=request_id, name="python pipeline")
    yield pb.SubmitJobRequest(spec=spec)
    for at in range(0, len(data), 1 << 15):
        yield pb.SubmitJobRequest(chunk=data[at:at + (1 << 15)])


def check_m4d(mesh, stats):
    """The .m4d layout of docs/mesh-format.md, read without mesh4d's own code."""
    assert mesh[:8] == b"MESH4D\0\n", f"magic {mesh[:8]!r}"
    version, _flags, v, p, b = struct.unpack_from("<IIQQQ", mesh, 8)
    assert version == 1, f"version {version}"
    pad8 = lambda n: (n + 7) // 8 * 8
    expected = 64 + 32 * v + pad8(v) + pad8(20 * p) + pad8(2 * p) + 24 * b + 32
    assert len(mesh) == expected, f"{len(mesh)} bytes, the counts say {expected}"
    assert hashlib.sha256(mesh[:-32]).digest() == mesh[-32:], "checksum"
    assert (v, p, b) == (stats.vertices, stats.pentatopes, stats.boundary_tetrahedra), \
        f"counts {(v, p, b)} against the final event's statistics"
    offset = 64 + 32 * v + pad8(v)
    corners = numpy.frombuffer(mesh, dtype="<u4", count=5 * p, offset=offset)
    assert corners.max() < v, "vertex index out of range"
    labels = numpy.frombuffer(mesh, dtype="<u2", count=p, offset=offset + pad8(20 * p))
    assert set(numpy.unique(labels).tolist()) == {1}, f"labels {numpy.unique(labels)}"
    return v, p, b


def run(server_bin, proto_dir, folder):
    generate_stubs(proto_dir, os.path.join(folder, "stubs"))
    import grpc
    import health_pb2
    import health_pb2_grpc
    from mesh4d.v1 import mesh4d_pb2 as pb, mesh4d_pb2_grpc as pb_grpc

    process, ports = start_server(server_bin, folder)
    port = ports["grpc"]
    try:
        channel = grpc.insecure_channel(f"127.0.0.1:{port}")
        health = health_pb2_grpc.HealthStub(channel).Check(health_pb2.HealthCheckRequest(),
                                                           timeout=10)
        assert health.status == health_pb2.HealthCheckResponse.SERVING, health
        service = pb_grpc.MeshServiceStub(channel)

        dims = 16
        data = hypersphere(dims, 5.5)
        response = service.SubmitJob(submit_requests(pb, data, "py-1", dims), timeout=60)
        job_id = response.job.id
        assert job_id and not response.deduplicated, response
        print(f"submitted job {job_id}")

        states, vertices, stats = [], [], None
        events = service.WatchJob(pb.WatchJobRequest(job_id=job_id), timeout=120)
        previous = None
        for event in events:
            if previous is not None:
                assert event.sequence == previous + 1, f"sequence {previous} -> {event.sequence}"
            previous = event.sequence
            kind = event.WhichOneof("event")
            if kind == "snapshot":
                assert event.snapshot.id == job_id
            elif kind == "progress":
                vertices.append(event.progress.vertices)
            elif kind == "finished":
                stats = event.finished
            elif kind == "state":
                states.append(pb.JobState.Name(event.state))
                if event.state in (pb.JOB_STATE_SUCCEEDED, pb.JOB_STATE_FAILED,
                                   pb.JOB_STATE_CANCELLED):
                    break
        assert states and states[-1] == "JOB_STATE_SUCCEEDED", f"states {states}"
        assert stats is not None and stats.pentatopes > 0, "no final statistics"
        assert vertices == sorted(vertices), f"vertex counts fell: {vertices}"
        print(f"watched {previous + 1} events: states {states}, {len(vertices)} progress, "
              f"{stats.pentatopes} pentatopes")

        again = service.SubmitJob(submit_requests(pb, data, "py-1", dims), timeout=60)
        assert again.deduplicated and again.job.id == job_id, "a retried submit made a new job"

        header, chunks = None, []
        for message in service.GetResult(pb.GetResultRequest(job_id=job_id), timeout=60):
            if message.WhichOneof("payload") == "header":
                header = message.header
            else:
                chunks.append(message.chunk)
        mesh = b"".join(chunks)
        assert header is not None and header.byte_size == len(mesh), "result size"
        assert hashlib.sha256(mesh).digest() == header.sha256, "result SHA-256"
        v, p, b = check_m4d(mesh, stats)
        print(f"fetched {len(mesh)} bytes: {v} vertices, {p} pentatopes, {b} boundary tetrahedra")

        try:
            service.GetJob(pb.GetJobRequest(job_id="no-such-job"), timeout=10)
            raise AssertionError("an unknown job id was accepted")
        except grpc.RpcError as error:
            assert error.code() == grpc.StatusCode.NOT_FOUND, error
            print(f"unknown id: {error.code().name}: {error.details()}")

        service.DeleteJob(pb.DeleteJobRequest(job_id=job_id), timeout=10)
        listed = service.ListJobs(pb.ListJobsRequest(), timeout=10)
        assert all(job.id != job_id for job in listed.jobs), "a deleted job is still listed"
    finally:
        process.send_signal(signal.SIGTERM)
        try:
            code = process.wait(timeout=20)
        except subprocess.TimeoutExpired:
            process.kill()
            raise AssertionError("the server did not stop on SIGTERM")
    assert code == 0, f"the server exited with {code}"


def main():
    server_bin, proto_dir = sys.argv[1], sys.argv[2]
    with tempfile.TemporaryDirectory() as folder:
        run(server_bin, proto_dir, folder)
    print("python grpc client: passed")


if __name__ == "__main__":
    main()
