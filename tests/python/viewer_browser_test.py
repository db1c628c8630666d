#!/usr/bin/python3
"""The dashboard's mesh viewer in a real browser: Debian's headless Chromium (WebGL in software,
SwiftShader) opens a finished job of the beating ventricle. Through the DevTools protocol the test
waits until the canvas shows the time slice, checks that the viewer drew exactly the triangles of
the server's slice at that instant (decoded here from /slices/{t}.surface, and counted apart from
the .vtu boundary slice), moves the time slider, and checks that the canvas shows the mesh (pixels
off the background) and that its pixels changed between the two instants. Colouring by quality
redraws the same triangles. Two screenshots are kept in OUT_DIR (viewer_t1.png, viewer_t2.png).

usage: viewer_browser_test.py SERVER_BINARY PHANTOM_BINARY OUT_DIR
"""
import json
import os
import re
import struct
import sys
import time
import urllib.request

from browser import finish, start_chromium, stop
from mesh4d_server import ventricle_server

# WebGL without a GPU: ANGLE on SwiftShader.
FLAGS = ["--window-size=1100,1300", "--use-angle=swiftshader", "--enable-unsafe-swiftshader"]

# The viewer's canvas as pixels: how many differ from the background, and the pixels themselves
# kept in window.lastPixels for the comparison with the next instant.
READ_CANVAS = """(() => {
  const canvas = document.getElementById('viewer');
  const copy = document.createElement('canvas');
  copy.width = canvas.width; copy.height = canvas.height;
  const g = copy.getContext('2d');
  g.drawImage(canvas, 0, 0);
  const px = g.getImageData(0, 0, copy.width, copy.height).data;
  const bg = [px[0], px[1], px[2]];
  let drawn = 0, changed = 0;
  for (let i = 0; i < px.length; i += 4) {
    if (Math.abs(px[i] - bg[0]) + Math.abs(px[i + 1] - bg[1]) + Math.abs(px[i + 2] - bg[2]) > 24)
      ++drawn;
    if (window.lastPixels && (px[i] !== window.lastPixels[i] || px[i + 1] !== window.lastPixels[i + 1]
        || px[i + 2] !== window.lastPixels[i + 2]))
      ++changed;
  }
  window.lastPixels = px;
  return JSON.stringify({ width: copy.width, height: copy.height, drawn, changed });
})()"""


def set_control(tools, element, value, event):
    """Sets a form control as a person would, with the event the page listens to."""
    tools.evaluate(f"{{ const e = document.getElementById({json.dumps(element)});"
                   f"e.value = {json.dumps(value)}; e.dispatchEvent(new Event('{event}')); }} 0")


def viewer_state(tools):
    text = tools.evaluate("window.mesh4dViewer ? JSON.stringify(window.mesh4dViewer()) : ''")
    return json.loads(text) if text else None


def wait_for_draw(tools, job, drawn_before, timeout=120):
    deadline = time.time() + timeout
    while time.time() < deadline:
        state = viewer_state(tools)
        if state and state["job"] == job and state["drawn"] > drawn_before:
            time.sleep(0.3)  # the frame after the draw
            return viewer_state(tools)
        time.sleep(0.2)
    return None


def server_triangles(base, job, t):
    """The triangles of the slice at t: from the compact surface, and from the .vtu boundary."""
    data = urllib.request.urlopen(f"{base}/v1/jobs/{job}/slices/{t!r}.surface").read()
    magic, version = data[:4], struct.unpack_from("<I", data, 4)[0]
    if magic != b"M4DS" or version != 1:
        raise SystemExit(f"unexpected surface header {magic} {version}")
    points, triangles = struct.unpack_from("<II", data, 32)
    vtu = urllib.request.urlopen(f"{base}/v1/jobs/{job}/slices/{t!r}.vtu?boundary=1").read()
    cells = int(re.search(rb'NumberOfCells="(\d+)"', vtu).group(1))
    return triangles, cells


def check_instant(tools, base, job, state, out_dir, name, failures):
    """The canvas at the instant `state` shows: its pixels, a screenshot, and its triangles
    against the server's slice there."""
    canvas = json.loads(tools.evaluate(READ_CANVAS))
    print(f"{name}: {state}, canvas {canvas}")
    tools.screenshot(os.path.join(out_dir, f"viewer_{name}.png"))
    surface, vtu = server_triangles(base, job, state["time"])
    if state["triangles"] != surface or surface != vtu:
        failures.append(f"drawn {state['triangles']} triangles at t = {state['time']}; the "
                        f"server's slice has {surface} (.surface) and {vtu} (.vtu)")
    return canvas


def main():
    server_bin, phantom_bin, out_dir = sys.argv[1:4]
    os.makedirs(out_dir, exist_ok=True)
    folder, image, server, base = ventricle_server(server_bin, phantom_bin, "mesh4d-viewer-")
    chromium = None
    failures = []
    try:
        request = urllib.request.Request(f"{base}/v1/jobs?name=ventricle",
                                         data=open(image, "rb").read(), method="POST")
        job = json.load(urllib.request.urlopen(request, timeout=60))["job"]["id"]
        deadline = time.time() + 300
        while time.time() < deadline:
            state = json.load(urllib.request.urlopen(f"{base}/v1/jobs/{job}"))["state"]
            if state not in ("JOB_STATE_QUEUED", "JOB_STATE_RUNNING"):
                break
            time.sleep(0.5)
        if state != "JOB_STATE_SUCCEEDED":
            raise SystemExit(f"the job ended {state}")

        chromium, tools = start_chromium(base + "/", f"{folder}/profile", FLAGS)
        # The page selects the finished job and draws an instant mid-cycle.
        first = wait_for_draw(tools, job, 0)
        if not first:
            info = tools.evaluate("document.getElementById('viewer-info').textContent")
            raise SystemExit(f"the viewer drew nothing: {info!r}")
        canvas = check_instant(tools, base, job, first, out_dir, "t1", failures)
        if canvas["drawn"] < 0.02 * canvas["width"] * canvas["height"]:
            failures.append(f"the canvas shows almost nothing of the mesh: {canvas}")

        # The slider to another instant of the cycle.
        set_control(tools, "time", 40, "input")
        second = wait_for_draw(tools, job, first["drawn"])
        if not second or second["time"] == first["time"]:
            failures.append(f"moving the slider drew no other instant: {second}")
        else:
            canvas = check_instant(tools, base, job, second, out_dir, "t2", failures)
            if canvas["changed"] < 0.002 * canvas["width"] * canvas["height"]:
                failures.append(f"the canvas hardly changed between the instants: {canvas}")
            # Colour by quality: the same triangles again, in other colours.
            set_control(tools, "color-by", "ratio", "change")
            third = wait_for_draw(tools, job, second["drawn"])
            canvas = json.loads(tools.evaluate(READ_CANVAS))
            legend = tools.evaluate("document.getElementById('legend').textContent")
            print("coloured by radius-edge ratio:", third, canvas, legend)
            if not third or third["triangles"] != second["triangles"] or canvas["changed"] == 0:
                failures.append(f"colouring by quality did not redraw the slice: {third}")
            if "radius-edge ratio" not in legend:
                failures.append(f"the legend does not name the quality: {legend!r}")
    finally:
        stop(chromium, server)
    finish(failures, folder)


if __name__ == "__main__":
    main()
