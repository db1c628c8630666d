"""The real mesh4d-server for the Python tests: started on loopback ports chosen by the system
(gRPC, metrics and HTTP), one thread a job, its log beside its data."""
import os
import subprocess
import sys
import tempfile
import time


def start_server(server_bin, folder, extra=()):
    """Returns (process, ports) with ports = {"grpc", "metrics", "http"}; `extra`: more flags."""
    port_file = os.path.join(folder, "port")
    log = open(os.path.join(folder, "server.log"), "w")
    process = subprocess.Popen([server_bin, "--listen", "127.0.0.1:0", "--port-file", port_file,
                                "--data-dir", os.path.join(folder, "data"),
                                "--metrics-listen", "127.0.0.1:0", "--http-listen", "127.0.0.1:0",
                                "--threads-per-job", "1", *extra],
                               stdout=log, stderr=subprocess.STDOUT)
    deadline = time.monotonic() + 20
    while time.monotonic() < deadline:
        if os.path.exists(port_file):
            with open(port_file) as f:
                lines = f.read().split()
            if len(lines) >= 3:
                return process, dict(zip(("grpc", "metrics", "http"), map(int, lines)))
        if process.poll() is not None:
            break
        time.sleep(0.05)
    process.kill()
    sys.exit("the server did not start; its log:\n" + open(log.name).read())


def ventricle_server(server_bin, phantom_bin, prefix):
    """A fresh folder with the beating ventricle phantom written by mesh4d-phantom, and a server
    on it: (folder, image path, process, http base URL)."""
    folder = tempfile.mkdtemp(prefix=prefix)
    image = os.path.join(folder, "ventricle.nii.gz")
    subprocess.run([phantom_bin, "ventricle", "--out", image], check=True, capture_output=True)
    process, ports = start_server(server_bin, folder)
    return folder, image, process, f"http://127.0.0.1:{ports['http']}"
