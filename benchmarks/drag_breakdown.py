"""Where a drag's time goes outside the widget: helpers of ``bench_drag.py --breakdown``.

Two measurements the page's own latency records cannot make:

* :func:`server_round_trip` -- the empty-message round trip through the Jupyter server and the kernel
  *without a browser*: a Python websocket client on the kernel's channels sends the widget's debug ``ping``
  as a comm message and waits for its ``pong`` (the same handler the page's ping reaches). The difference to
  the page's ping is what the browser adds (its network process, the page's main thread).
* :func:`main_thread_split` -- the page's main-thread time per move from the V8 CPU profile of a Chrome trace
  (category ``disabled-by-default-v8.cpu_profiler``), split by who runs: the widget's ES modules (anywidget
  loads them from blob URLs), JupyterLab's reactions to the kernel's ``status`` messages (every comm message
  makes the kernel publish ``busy`` and ``idle``: the kernel status model, the toolbar, the busy favicon),
  the rest of JupyterLab's message handling (websocket, deserialization, comm dispatch), other script, and
  the browser's own work outside script (style, layout, paint, commit: ``(program)`` in the profile).
"""
from __future__ import annotations

import asyncio
import collections
import concurrent.futures
import json
import re
import statistics
import struct
import time
import uuid

#: Functions (names survive minification: they are methods) of JupyterLab's handling of kernel status.
STATUS_FUNCTIONS = ("_updateStatus", "_onStatusChanged", "onKernelStatus", "setBusy", "childItemsChanged")
#: Functions of JupyterLab's and ipywidgets' handling of any kernel message.
MESSAGE_FUNCTIONS = ("_onWSMessage", "_handleMessage", "deserializeV1KernelWebsocketJupyterOrg", "_handleCommMsg",
                     "handleMsg", "_handle_comm_msg")
#: anywidget loads an ES module from a blob URL: ``http://host:port/<uuid>``.
_WIDGET_URL = re.compile(r"/[0-9a-f]{8}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{12}$")
PARTS = ("widget", "kernel status (JupyterLab)", "messages (JupyterLab, ipywidgets)", "other script", "browser (program)")


def _heaviest_profile(events: list) -> tuple[dict, list, list]:
    """Nodes, samples and time deltas (us) of the V8 profile with the most samples (the page's main thread)."""
    profiles = collections.defaultdict(lambda: {"nodes": {}, "samples": [], "deltas": []})
    for event in events:
        if event.get("name") not in ("Profile", "ProfileChunk"):
            continue
        profile = profiles[(event["pid"], event.get("id"))]
        data = event["args"].get("data", {})
        chunk = data.get("cpuProfile", {})
        profile["nodes"].update({node["id"]: node for node in chunk.get("nodes", [])})
        profile["samples"] += chunk.get("samples", [])
        profile["deltas"] += data.get("timeDeltas", [])
    if not profiles:
        raise ValueError("the trace has no V8 CPU profile (record it with disabled-by-default-v8.cpu_profiler)")
    best = max(profiles.values(), key=lambda profile: len(profile["samples"]))
    return best["nodes"], best["samples"], best["deltas"]


def _part_of(node_id: int, nodes: dict, cache: dict) -> str | None:
    """Which of :data:`PARTS` a sample whose leaf is ``node_id`` belongs to (None: idle, GC roots)."""
    if node_id in cache:
        return cache[node_id]
    names, urls = [], []
    node = nodes.get(node_id)
    leaf = node["callFrame"].get("functionName") if node else ""
    while node is not None:
        frame = node["callFrame"]
        names.append(frame.get("functionName", ""))
        urls.append(frame.get("url", ""))
        node = nodes.get(node.get("parent"))
    if leaf in ("(idle)", "(root)", "(garbage collector)"):
        part = None if leaf != "(garbage collector)" else "other script"
    elif leaf == "(program)":
        part = "browser (program)"
    elif any(_WIDGET_URL.search(url) for url in urls):
        part = "widget"
    elif any(name in STATUS_FUNCTIONS for name in names):
        part = "kernel status (JupyterLab)"
    elif any(name in MESSAGE_FUNCTIONS for name in names):
        part = "messages (JupyterLab, ipywidgets)"
    else:
        part = "other script"
    cache[node_id] = part
    return part


def main_thread_split(trace_path, moves: int) -> dict:
    """Main-thread time per move (ms) by :data:`PARTS`, from the CPU profile in the Chrome trace at ``trace_path``."""
    events = json.loads(open(trace_path).read())
    events = events["traceEvents"] if isinstance(events, dict) else events
    nodes, samples, deltas = _heaviest_profile(events)
    totals = dict.fromkeys(PARTS, 0.0)
    cache: dict = {}
    # a sample's delta is the time since the previous sample: it belongs to the sample it precedes
    for node_id, delta in zip(samples, deltas[1:] + [0]):
        part = _part_of(node_id, nodes, cache)
        if part is not None:
            totals[part] += delta / 1e3
    return {part: value / moves for part, value in totals.items()}


def _decode(raw) -> dict:
    """A kernel message from the server's websocket (JSON text, or the binary framing with buffers)."""
    if isinstance(raw, bytes):
        count = struct.unpack("!I", raw[:4])[0]
        offsets = struct.unpack(f"!{count}I", raw[4:4 + 4 * count])
        return json.loads(raw[offsets[0]:offsets[1]] if count > 1 else raw[offsets[0]:])
    return json.loads(raw)


async def _round_trips(url: str, token: str, kernel_id: str, comm_id: str, count: int) -> list:
    from tornado.websocket import websocket_connect

    session = uuid.uuid4().hex
    socket = await websocket_connect(
        f"{url.replace('http', 'ws', 1)}/api/kernels/{kernel_id}/channels?session_id={session}&token={token}")
    times = []
    try:
        for k in range(count):
            ping_id = 10**9 + k  # the page's own pings count from 1: it ignores these pongs
            header = {"msg_id": uuid.uuid4().hex, "username": "bench", "session": session, "msg_type": "comm_msg",
                      "version": "5.3", "date": ""}
            content = {"comm_id": comm_id, "data": {"method": "custom", "content": {"type": "ping", "id": ping_id}}}
            started = time.perf_counter()
            await socket.write_message(json.dumps({"header": header, "parent_header": {}, "metadata": {},
                                                   "content": content, "channel": "shell", "buffers": []}))
            while True:
                message = _decode(await socket.read_message())
                data = message.get("content", {}).get("data", {})
                if message["header"]["msg_type"] == "comm_msg" and data.get("content", {}).get("id") == ping_id:
                    times.append(1e3 * (time.perf_counter() - started))
                    break
    finally:
        socket.close()
    return times


def server_round_trip(server, comm_id: str, count: int = 60, warmup: int = 10) -> float:
    """Median round trip (ms) of the widget's debug ping through ``server`` and its only kernel, no browser."""
    kernels = server.api("/api/kernels")
    if len(kernels) != 1:
        raise ValueError(f"expected one running kernel, found {len(kernels)}")
    coroutine = _round_trips(server.url, server.token, kernels[0]["id"], comm_id, count + warmup)
    # a thread of its own: Playwright's synchronous API keeps an event loop running in this one
    with concurrent.futures.ThreadPoolExecutor(max_workers=1) as pool:
        times = pool.submit(asyncio.run, coroutine).result()
    return statistics.median(times[warmup:])
