#!/usr/bin/python3
"""The dashboard in a real browser: Debian's headless Chromium loads / from the real
mesh4d-server while a job runs; through the DevTools protocol (python3-websocket) the test reads
the page's DOM every half second and checks that the live progress numbers rise, and that the
finished job shows its quality table, its fidelity certificate (each label's row as the REST face
gives it, defects marked), its normalized-volume histogram with labelled axes, the live plot of
its progress (vertices, pentatopes, each rule's insertions over time) and a download link. The
job's name is markup that would run a script if the page took it as HTML: it must show as text.
Then a server with a token: the page asks for it, signs in (an HttpOnly cookie), and shows the
jobs and a job's events, with the token in no URL and not readable by the page's scripts. A
screenshot of the finished page is kept in OUT_DIR/dashboard.png.

usage: dashboard_browser_test.py SERVER_BINARY PHANTOM_BINARY OUT_DIR
"""
import json
import os
import signal
import sys
import time
import urllib.parse
import urllib.request

from browser import finish, start_chromium, stop
from mesh4d_server import start_server, ventricle_server

FLAGS = ["--disable-gpu", "--window-size=1200,1100"]

# What the test reads from the page (the dashboard's own element ids).
READ_PAGE = """JSON.stringify({
  job: document.getElementById('job-id').textContent,
  state: document.getElementById('job-state').textContent,
  vertices: document.getElementById('vertices').textContent,
  pentatopes: document.getElementById('pentatopes').textContent,
  quality_rows: document.querySelectorAll('#quality tbody tr').length,
  certificate: Array.from(document.querySelectorAll('#certificate tbody tr')).map(
      tr => Array.from(tr.children).map(td => td.textContent)),
  defects: document.querySelectorAll('#certificate td.defect').length,
  result_shown: !document.getElementById('result').hidden,
  bars: document.querySelectorAll('#histogram rect.bar').length,
  histogram_text: Array.from(document.querySelectorAll('#histogram text')).map(t => t.textContent),
  plotted: Array.from(document.querySelectorAll('#plot-size polyline, #plot-rules polyline'))
      .map(l => l.points.numberOfItems),
  plot_text: Array.from(document.querySelectorAll('#plot-size text, #plot-rules text'))
      .map(t => t.textContent),
  download: document.getElementById('download').getAttribute('href'),
  names: Array.from(document.querySelectorAll('#jobs tbody td:nth-child(2)')).map(td => td.textContent),
  images: document.querySelectorAll('#jobs img').length,
  pwned: window.pwned === 1,
  login_shown: !!document.getElementById('login') && !document.getElementById('login').hidden,
  url: location.href,
  cookies: document.cookie
})"""

# A job name that runs a script wherever it is taken as HTML.
MARKUP_NAME = '<img src=x onerror="window.pwned=1">'


def read_page(tools):
    text = tools.evaluate(READ_PAGE)
    return json.loads(text) if text else None  # None: the page is still loading


def count(text):
    return int(text.replace(",", "")) if text.strip() else 0


def check_token_sign_in(tools, server_bin, folder, image):
    """A server with a token: the dashboard signs in without putting the token in a URL."""
    failures = []
    token = "s3cret-token"
    secured_dir = os.path.join(folder, "secured")
    os.makedirs(secured_dir)
    server, ports = start_server(server_bin, secured_dir, ["--token", token])
    base = f"http://127.0.0.1:{ports['http']}"
    try:
        request = urllib.request.Request(f"{base}/v1/jobs?delta=6&threads=1&name=secured",
                                         data=open(image, "rb").read(), method="POST",
                                         headers={"Authorization": "Bearer " + token})
        job = json.load(urllib.request.urlopen(request, timeout=60))["job"]["id"]
        tools.call("Page.navigate", url=base + "/")
        page = None
        deadline = time.time() + 60
        while time.time() < deadline:
            page = read_page(tools)
            if page and page["login_shown"]:
                break
            time.sleep(0.2)
        if not page or not page["login_shown"]:
            failures.append(f"no sign-in form on a server with a token: {page}")
            return failures
        tools.call("Runtime.evaluate", expression=(
            f"document.getElementById('token').value = {json.dumps(token)};"
            "document.getElementById('login').requestSubmit()"))
        deadline = time.time() + 120
        while time.time() < deadline:
            page = read_page(tools)
            if page and page["job"] == job and page["state"]:
                break
            time.sleep(0.3)
        print("signed-in page:", page)
        if not page or page["job"] != job or not page["state"]:
            failures.append(f"after signing in the job and its events do not show: {page}")
        elif token in page["url"] or token in page["cookies"] or page["login_shown"]:
            failures.append(f"the token is in the URL or readable by the page: {page}")
    finally:
        server.send_signal(signal.SIGTERM)
        server.wait(timeout=30)
    return failures


def check_certificate(page, base, job):
    """The certificate table shows, per label, what the REST face says of the job."""
    stats = json.load(urllib.request.urlopen(f"{base}/v1/jobs/{job}", timeout=30))["stats"]
    labels = stats.get("certificate", [])
    rows = page["certificate"]
    print("certificate rows:", rows)
    if not labels or len(rows) != len(labels):
        return [f"the certificate table has {len(rows)} rows for {len(labels)} labels"]
    failures = []
    defects = 0
    for row, c in zip(rows, labels):
        n = {k: int(c.get(k, 0)) for k in ("label", "mesh_pieces", "image_pieces",
                                          "touching_pieces", "non_manifold_vertices",
                                          "non_manifold_edges", "non_manifold_triangles")}
        wanted = [str(n["label"]), f"{n['mesh_pieces']:,} / {n['image_pieces']:,}",
                  f"{n['touching_pieces']:,}",
                  f"{n['non_manifold_vertices']:,} / {n['non_manifold_edges']:,} / "
                  f"{n['non_manifold_triangles']:,}",
                  f"{c['volume'] / c['voxel_volume']:.4f}"]
        distance = (f"{c.get('mesh_to_image_max', 0):.3f} ({c.get('mesh_to_image_mean', 0):.3f}), "
                    f"{c.get('image_to_mesh_max', 0):.3f} ({c.get('image_to_mesh_mean', 0):.3f})")
        if int(c.get("distance_samples", 0)) == 0:
            failures.append(f"label {n['label']}: no boundary distance measured")
        if row[:5] != wanted or row[6:7] != [distance]:
            failures.append(f"certificate row {row} is not the job's {wanted}, {distance}")
        defects += (n["mesh_pieces"] != n["image_pieces"]) + (n["touching_pieces"] > 0) + (
            n["non_manifold_vertices"] + n["non_manifold_edges"] + n["non_manifold_triangles"] > 0)
    if page["defects"] != defects:
        failures.append(f"{page['defects']} cells marked as defects, the job has {defects}")
    return failures


def main():
    server_bin, phantom_bin, out_dir = sys.argv[1:4]
    os.makedirs(out_dir, exist_ok=True)
    folder, image, server, base = ventricle_server(server_bin, phantom_bin, "mesh4d-dashboard-")
    chromium = None
    failures = []
    try:
        chromium, tools = start_chromium(base + "/", f"{folder}/profile", FLAGS)
        # The page first, then the job: a job that ended while the browser was still starting
        # (a loaded machine) would leave nothing to watch.
        deadline = time.time() + 120
        while read_page(tools) is None and time.time() < deadline:
            time.sleep(0.2)
        # A job long enough to watch (one thread, a fine delta).
        request = urllib.request.Request(
            f"{base}/v1/jobs?delta=3&threads=1&name={urllib.parse.quote(MARKUP_NAME)}",
            data=open(image, "rb").read(), method="POST")
        job = json.load(urllib.request.urlopen(request, timeout=60))["job"]["id"]
        seen, final = [], None
        deadline = time.time() + 300
        while time.time() < deadline:
            page = read_page(tools)
            if page is None:
                time.sleep(0.2)
                continue
            if page["job"] == job and page["state"] == "RUNNING" and page["vertices"]:
                seen.append(count(page["vertices"]))
            if page["state"] == "SUCCEEDED" and page["result_shown"] and page["quality_rows"]:
                final = page
                break
            time.sleep(0.5)
        rises = sum(1 for a, b in zip(seen, seen[1:]) if b > a)
        print(f"vertex counts seen while running: {seen[:3]} ... {seen[-3:]} ({rises} rises)")
        if rises < 2:
            failures.append(f"the live vertex count rose {rises} times (needs 2): {seen}")
        if any(b < a for a, b in zip(seen, seen[1:])):
            failures.append(f"the vertex count fell: {seen}")
        if not final:
            failures.append("the finished job never showed its quality table")
        else:
            print("finished page:", final)
            if final["job"] != job:
                failures.append(f"the page shows job {final['job']}, not {job}")
            if final["quality_rows"] != 2:
                failures.append("the quality table lacks its two rows")
            if final["bars"] < 10:
                failures.append("the normalized-volume histogram is missing")
            for label in ("normalized volume", "pentatopes", "0", "1"):
                if label not in final["histogram_text"]:
                    failures.append(f"the histogram has no axis text {label!r}")
            # The live plot: vertices, pentatopes and five rules, a point per progress report.
            if len(final["plotted"]) != 7 or min(final["plotted"]) < 3:
                failures.append(f"the progress plot lacks its lines: {final['plotted']}")
            for label in ("vertices", "pentatopes", "R1", "R5", "elapsed s", "insertions"):
                if label not in final["plot_text"]:
                    failures.append(f"the progress plot has no text {label!r}")
            if final["download"] != f"/v1/jobs/{job}/mesh":
                failures.append(f"download link {final['download']}")
            if count(final["pentatopes"]) <= 0:
                failures.append("no pentatope count")
            failures += check_certificate(final, base, job)
            if MARKUP_NAME not in final["names"] or final["images"] or final["pwned"]:
                failures.append(f"the job's name was taken as markup: {final}")
        tools.screenshot(os.path.join(out_dir, "dashboard.png"))
        failures += check_token_sign_in(tools, server_bin, folder, image)
    finally:
        stop(chromium, server)
    finish(failures, folder)


if __name__ == "__main__":
    main()
