#!/usr/bin/python3
"""The dashboard's submission form and mesh viewer in a real browser: Debian's headless Chromium
(WebGL in software, SwiftShader) submits a file that is no image through the form (the form must
say why), then the beating ventricle (δ 6, periodic time, a name: the job must carry them).
Through the DevTools protocol the test waits until the finished job's canvas shows the time slice, checks that the viewer drew exactly the triangles of
the server's slice at that instant (decoded here from /slices/{t}.surface, and counted apart from
the .vtu boundary slice), moves the time slider, and checks that the canvas shows the mesh (pixels
off the background) and that its pixels changed between the two instants. Colouring by quality
redraws the same triangles, and so does seeing through the outer surface. The screenshots are
kept in OUT_DIR (viewer_t1.png, viewer_t2.png, viewer_see_through.png).

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


def wait_for(read, what, timeout=300):
    """read()'s first truthy value, polled; exits when none comes."""
    deadline = time.time() + timeout
    while time.time() < deadline:
        value = read()
        if value:
            return value
        time.sleep(0.3)
    raise SystemExit(f"timed out waiting for {what}")


def submit_form(tools, path, fields):
    """Fills the page's submission form (the file through DevTools, as a person picks one) and
    submits it."""
    node = tools.call("Runtime.evaluate", expression="document.getElementById('submit-file')")
    tools.call("DOM.setFileInputFiles", files=[path], objectId=node["result"]["objectId"])
    for element, value in fields.items():
        set_control(tools, element, value, "change")
    tools.evaluate("document.getElementById('submit-form').requestSubmit(); 0")


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


def slider_time(tools):
    """The instant the slider names, as the page computes it."""
    return float(tools.evaluate("String(stepTime(Number(document.getElementById('time').value)))"))


def shows_slider_time(state, t):
    return state is not None and abs(state["time"] - t) <= 1e-9 * max(1.0, abs(t))


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
        chromium, tools = start_chromium(base + "/", f"{folder}/profile", FLAGS)
        # The dashboard's script ran (the first target can still be about:blank).
        wait_for(lambda: tools.evaluate("document.readyState === 'complete' && "
                                        "typeof showMesh === 'function'"), "the page to load")
        # A file that is no image: the form says why, and no job is made.
        junk = os.path.join(folder, "notes.nii.gz")
        open(junk, "w").write("not an image")
        submit_form(tools, junk, {"submit-delta": 5})
        refused = wait_for(lambda: tools.evaluate(
            "document.getElementById('submit-status').className === 'failed' && "
            "document.getElementById('submit-status').textContent"), "the refusal")
        print("a junk file:", refused)
        if "INVALID_ARGUMENT" not in refused:
            failures.append(f"the form's refusal does not say why: {refused!r}")
        # The phantom through the form: δ 6, periodic time, a name.
        submit_form(tools, image, {"submit-delta": 6, "submit-time": "periodic",
                                   "submit-name": "form-ventricle"})
        jobs = wait_for(lambda: json.load(urllib.request.urlopen(f"{base}/v1/jobs"))["jobs"],
                        "the submitted job")
        job = jobs[0]["id"]
        params = jobs[0]["params"]
        print("submitted through the form:", job, jobs[0]["name"], params)
        if (len(jobs) != 1 or jobs[0]["name"] != "form-ventricle" or params["delta"] != 6
                or params["time_topology"] != "TIME_TOPOLOGY_PERIODIC"):
            failures.append(f"the form's job is not what was filled in: {jobs}")
        # The page selects the finished job and draws an instant mid-cycle.
        first = wait_for_draw(tools, job, 0)
        if not first:
            info = tools.evaluate("document.getElementById('viewer-info').textContent")
            raise SystemExit(f"the viewer drew nothing: {info!r}")
        canvas = check_instant(tools, base, job, first, out_dir, "t1", failures)
        if canvas["drawn"] < 0.02 * canvas["width"] * canvas["height"]:
            failures.append(f"the canvas shows almost nothing of the mesh: {canvas}")
        if first["drawn"] != 1 or not shows_slider_time(first, slider_time(tools)):
            failures.append(f"the first drawing is not the slider's mid-cycle instant "
                            f"{slider_time(tools)}: {first}")

        # The slider dragged to another instant of the cycle: the instants on the way are asked
        # for, and only the last is drawn, whatever order the answers come in.
        tools.evaluate("{ const e = document.getElementById('time');"
                       "  for (const v of [28, 32, 36, 40]) {"
                       "    e.value = v; e.dispatchEvent(new Event('input')); } } 0")
        second = wait_for_draw(tools, job, first["drawn"])
        time.sleep(1.0)  # time for any answer on the way to arrive
        settled = viewer_state(tools)
        if not second or second["time"] == first["time"]:
            failures.append(f"moving the slider drew no other instant: {second}")
        else:
            if (settled != second or second["drawn"] != first["drawn"] + 1
                    or not shows_slider_time(second, slider_time(tools))):
                failures.append(f"dragging the slider drew {second}, then {settled}: not once, "
                                f"at the slider's instant {slider_time(tools)}")
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
            # See-through: the outer surface faint, the same triangles, other pixels.
            tools.evaluate("{ const e = document.getElementById('see-through'); e.checked = true;"
                           " e.dispatchEvent(new Event('change')); } 0")
            fourth = wait_for_draw(tools, job, third["drawn"] if third else 0)
            canvas = json.loads(tools.evaluate(READ_CANVAS))
            print("see-through:", fourth, canvas)
            tools.screenshot(os.path.join(out_dir, "viewer_see_through.png"))
            if not fourth or fourth["triangles"] != second["triangles"] or canvas["changed"] == 0:
                failures.append(f"see-through did not redraw the slice: {fourth} {canvas}")
    finally:
        stop(chromium, server)
    finish(failures, folder)


if __name__ == "__main__":
    main()
