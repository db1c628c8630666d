"""Debian's headless Chromium for the dashboard tests, driven through the DevTools protocol
(python3-websocket): start it on a page, evaluate scripts there, take screenshots, and the tests'
common ending."""
import base64
import json
import shutil
import signal
import subprocess
import sys
import time
import urllib.request

import websocket

CHROMIUM_FLAGS = ["--headless", "--no-sandbox", "--disable-background-networking",
                  "--disable-component-update", "--disable-sync", "--remote-debugging-port=0"]


def devtools_page(chromium):
    """The page target's websocket, from the browser's 'DevTools listening on' line."""
    deadline = time.time() + 60
    while time.time() < deadline:
        line = chromium.stderr.readline().decode(errors="replace")
        if "DevTools listening on ws://" in line:
            port = int(line.split("ws://127.0.0.1:")[1].split("/")[0])
            break
    else:
        raise SystemExit("chromium did not open its DevTools port")
    for _ in range(100):
        targets = json.load(urllib.request.urlopen(f"http://127.0.0.1:{port}/json/list"))
        pages = [t for t in targets if t["type"] == "page"]
        if pages:
            return websocket.create_connection(pages[0]["webSocketDebuggerUrl"], timeout=30)
        time.sleep(0.1)
    raise SystemExit("chromium has no page")


class DevTools:
    def __init__(self, ws):
        self.ws, self.next_id = ws, 0

    def call(self, method, **params):
        self.next_id += 1
        self.ws.send(json.dumps({"id": self.next_id, "method": method, "params": params}))
        while True:
            message = json.loads(self.ws.recv())
            if message.get("id") == self.next_id:
                if "error" in message:
                    raise RuntimeError(f"{method}: {message['error']}")
                return message["result"]

    def evaluate(self, expression):
        """The expression's value (awaited when it is a promise); None while the page loads."""
        result = self.call("Runtime.evaluate", expression=expression, returnByValue=True,
                           awaitPromise=True)
        return result["result"].get("value")

    def screenshot(self, path):
        shot = self.call("Page.captureScreenshot", format="png")
        open(path, "wb").write(base64.b64decode(shot["data"]))
        print("screenshot:", path)


def start_chromium(url, profile, flags=()):
    """Chromium showing `url` with a fresh profile folder: (process, DevTools)."""
    chromium_bin = shutil.which("chromium")
    if not chromium_bin:
        raise SystemExit("chromium is not installed (scripts/setup installs it)")
    chromium = subprocess.Popen(
        [chromium_bin, *CHROMIUM_FLAGS, *flags, f"--user-data-dir={profile}", url],
        stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    return chromium, DevTools(devtools_page(chromium))


def stop(chromium, server):
    if chromium:
        chromium.kill()
        chromium.wait()
    server.send_signal(signal.SIGTERM)
    server.wait(timeout=30)


def finish(failures, folder):
    """Prints the failures and exits 1 keeping `folder`, or removes it."""
    for f in failures:
        print("FAIL:", f)
    if failures:
        print("kept for a look:", folder)
        sys.exit(1)
    shutil.rmtree(folder, ignore_errors=True)
