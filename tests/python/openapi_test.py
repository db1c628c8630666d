#!/usr/bin/python3
"""docs/openapi.yaml against the real mesh4d-server: every documented operation is called (its
success and, where the document lists them, its errors), every answer's status must be one the
document lists for that operation, and every JSON answer must carry its schema's required
properties (with their types). The server must serve the same document at /openapi.yaml, and a
path the document does not list must be 404.

usage: openapi_test.py SERVER_BINARY OPENAPI_YAML
"""
import json
import os
import shutil
import signal
import sys
import tempfile
import urllib.error
import urllib.request

import nibabel
import numpy as np
import yaml
from mesh4d_server import start_server

FAILURES = []


def check(condition, message):
    if not condition:
        FAILURES.append(message)
        print("FAIL:", message)


def request(base, method, path, body=None):
    req = urllib.request.Request(base + path, data=body, method=method)
    try:
        with urllib.request.urlopen(req, timeout=60) as r:
            return r.status, r.headers.get("Content-Type", ""), r.read()
    except urllib.error.HTTPError as e:
        return e.code, e.headers.get("Content-Type", ""), e.read()


def lookup(doc, ref):
    node = doc
    for part in ref.lstrip("#/").split("/"):
        node = node[part]
    return node


def deref(doc, node):
    while isinstance(node, dict) and "$ref" in node:
        node = lookup(doc, node["$ref"])
    return node


TYPES = {"string": str, "integer": int, "number": (int, float), "boolean": bool,
         "object": dict, "array": list}


def check_schema(doc, schema, value, where):
    schema = deref(doc, schema)
    kind = schema.get("type")
    if kind in TYPES:
        ok = isinstance(value, TYPES[kind]) and not (kind != "boolean" and isinstance(value, bool))
        check(ok, f"{where}: {type(value).__name__} where the document says {kind}")
        if not ok:
            return
    if "enum" in schema:
        check(value in schema["enum"], f"{where}: {value!r} is not one of {schema['enum']}")
    if kind == "object":
        for name in schema.get("required", []):
            check(name in value, f"{where}: required property {name!r} missing")
        for name, sub in schema.get("properties", {}).items():
            if name in value:
                check_schema(doc, sub, value[name], f"{where}.{name}")
    if kind == "array":
        for i, item in enumerate(value[:3]):
            check_schema(doc, schema.get("items", {}), item, f"{where}[{i}]")


def call(doc, base, template, method, path, body=None):
    """Calls and checks the answer against the document's responses for (template, method)."""
    operation = doc["paths"][template][method.lower()]
    status, content_type, payload = request(base, method, path, body)
    responses = operation["responses"]
    where = f"{method} {path} -> {status}"
    check(str(status) in responses, f"{where}: status not documented ({sorted(responses)})")
    response = deref(doc, responses.get(str(status), {}))
    content = response.get("content", {})
    if content:
        media = content_type.split(";")[0]
        check(media in content, f"{where}: Content-Type {media} not documented ({list(content)})")
        if media == "application/json" and media in content:
            check_schema(doc, content[media]["schema"], json.loads(payload), where)
    print(f"checked: {where}")
    return status, payload


def main():
    server_bin, doc_path = sys.argv[1], sys.argv[2]
    doc = yaml.safe_load(open(doc_path))
    folder = tempfile.mkdtemp(prefix="mesh4d-openapi-")
    # A small 4D ball, written by nibabel.
    g = np.mgrid[0:20, 0:20, 0:20, 0:20] - 9.5
    ball = (np.sqrt((g ** 2).sum(axis=0)) < 7).astype(np.uint8)
    image = os.path.join(folder, "ball.nii.gz")
    nibabel.save(nibabel.Nifti1Image(ball, np.eye(4)), image)
    body = open(image, "rb").read()

    process, ports = start_server(server_bin, folder)
    port = ports["http"]
    base = f"http://127.0.0.1:{port}"
    try:
        served = request(base, "GET", "/openapi.yaml")
        check(served[0] == 200 and served[2] == open(doc_path, "rb").read(),
              "the server serves docs/openapi.yaml at /openapi.yaml")
        status, payload = call(doc, base, "/v1/jobs", "POST", "/v1/jobs?delta=3&request_id=o-1",
                               body)
        job = json.loads(payload)["job"]["id"]
        call(doc, base, "/v1/jobs", "POST", "/v1/jobs?delta=3&request_id=o-1", body)  # 200
        call(doc, base, "/v1/jobs", "POST", "/v1/jobs?delta=-1", body)  # 400
        call(doc, base, "/v1/jobs/{id}/events", "GET", f"/v1/jobs/{job}/events")  # to the end
        call(doc, base, "/v1/jobs", "GET", "/v1/jobs")
        call(doc, base, "/v1/jobs", "GET", "/v1/jobs?state=bogus")
        call(doc, base, "/v1/jobs/{id}", "GET", f"/v1/jobs/{job}")
        call(doc, base, "/v1/jobs/{id}", "GET", "/v1/jobs/nope")
        call(doc, base, "/v1/jobs/{id}/mesh", "GET", f"/v1/jobs/{job}/mesh")
        call(doc, base, "/v1/jobs/{id}/mesh", "GET", "/v1/jobs/nope/mesh")
        call(doc, base, "/v1/jobs/{id}/slices/{t}.vtu", "GET", f"/v1/jobs/{job}/slices/9.5.vtu")
        call(doc, base, "/v1/jobs/{id}/slices/{t}.vtu", "GET", f"/v1/jobs/{job}/slices/x.vtu")
        status, surface = call(doc, base, "/v1/jobs/{id}/slices/{t}.surface", "GET",
                               f"/v1/jobs/{job}/slices/9.5.surface")
        check(status == 200 and surface[:4] == b"M4DS", "a slice surface starts with M4DS")
        call(doc, base, "/v1/jobs/{id}/slices/{t}.surface", "GET", "/v1/jobs/nope/slices/9.5.surface")
        call(doc, base, "/v1/jobs/{id}/cancel", "POST", f"/v1/jobs/{job}/cancel")
        call(doc, base, "/v1/jobs/{id}/cancel", "POST", "/v1/jobs/nope/cancel")
        call(doc, base, "/v1/jobs/{id}/events", "GET", "/v1/jobs/nope/events")
        call(doc, base, "/v1/jobs/{id}", "DELETE", f"/v1/jobs/{job}")
        call(doc, base, "/v1/jobs/{id}", "DELETE", f"/v1/jobs/{job}")  # 404 now
        call(doc, base, "/v1/login", "POST", "/v1/login", b'{"token": "any"}')  # no token: 204
        call(doc, base, "/v1/login", "POST", "/v1/login", b"not json")  # 400
        check(request(base, "GET", "/v1/nothing")[0] == 404, "an undocumented path is 404")
        # Every documented operation was called above.
        called = {("/v1/login", "post"), ("/v1/jobs", "get"), ("/v1/jobs", "post"),
                  ("/v1/jobs/{id}", "get"),
                  ("/v1/jobs/{id}", "delete"), ("/v1/jobs/{id}/cancel", "post"),
                  ("/v1/jobs/{id}/events", "get"), ("/v1/jobs/{id}/mesh", "get"),
                  ("/v1/jobs/{id}/slices/{t}.vtu", "get"),
                  ("/v1/jobs/{id}/slices/{t}.surface", "get")}
        documented = {(p, m) for p, ops in doc["paths"].items() for m in ops
                      if m in ("get", "post", "delete", "put")}
        check(documented == called, f"documented {sorted(documented - called)} not called, "
                                    f"called {sorted(called - documented)} not documented")
    finally:
        process.send_signal(signal.SIGTERM)
        process.wait(timeout=20)
    if FAILURES:
        print(f"{len(FAILURES)} failures; kept for a look: {folder}")
        sys.exit(1)
    shutil.rmtree(folder, ignore_errors=True)
    print("every call matches docs/openapi.yaml")


if __name__ == "__main__":
    main()
