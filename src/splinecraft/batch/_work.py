"""What a worker does with one batch of files: hash, trace, render, write atomically, report.

:func:`trace_batch` runs unchanged in every place a batch can run (the calling process, a thread, a local
worker process, a dask worker on another machine), so every scheduler writes the same bytes. It never
raises for a bad file: each file gets a record with ``status`` ``"ok"`` or ``"failed"`` and an ``error``
line. Outputs are written to a temporary file in the output's own directory and renamed over the output
(``os.replace``), so a reader never sees a half-written file; a failed write removes its temporary file.
"""
from __future__ import annotations

import hashlib
import json
import os
import signal
import sys
import tempfile
import threading
import time
import warnings

import numpy as np

from ..spline.svg import xml_safe

#: Suffix of the temporary files that outputs are written through (``.NAME.RANDOM.splinecraft-part``).
PART_SUFFIX = ".splinecraft-part"
#: Stats of each file kept in its record and in the manifest.
RECORD_STATS = ("boundaries", "holes", "contour_points", "corners", "knots_inserted", "segments",
                "iterations", "hausdorff", "converged", "polygons")
#: Wall-clock fields of ``TraceResult.stats`` left out of JSON outputs, so that outputs are reproducible.
TIMING_STATS = ("time_s", "time_breakdown", "time_per_boundary_s")

#: Stop events of runs in this process, by run id (threads and the synchronous scheduler look here
#: between files; a worker process has none and is stopped by its parent instead).
STOP_EVENTS: dict = {}
_CHUNK = 1 << 20


# ---------------------------------------------------------------------------------------------------
# hashes
# ---------------------------------------------------------------------------------------------------
def file_sha256(path) -> str:
    """SHA-256 of a file's bytes (hex)."""
    digest = hashlib.sha256()
    with open(path, "rb") as handle:
        for block in iter(lambda: handle.read(_CHUNK), b""):
            digest.update(block)
    return digest.hexdigest()


def input_sha256(source) -> str:
    """SHA-256 of an input: a file's bytes, encoded image bytes (the hash of that file), or an array's dtype,
    shape and pixels."""
    if isinstance(source, (str, os.PathLike)):
        return file_sha256(source)
    if isinstance(source, bytes):
        return hashlib.sha256(source).hexdigest()
    pixels = np.ascontiguousarray(np.asarray(source))
    digest = hashlib.sha256(f"{pixels.dtype.str}{pixels.shape}".encode())
    digest.update(pixels.tobytes())
    return digest.hexdigest()


# ---------------------------------------------------------------------------------------------------
# output
# ---------------------------------------------------------------------------------------------------
def render(result, fmt, decimals, title) -> bytes:
    """The output document of one traced file: ``TraceResult.to_svg`` or its JSON without wall times."""
    if fmt == "json":
        document = result.to_dict()
        for name in TIMING_STATS:
            document["stats"].pop(name, None)
        return json.dumps(document, allow_nan=False).encode("utf-8")
    # the title is the input's file name, which may hold bytes no encoding decoded (os.fsdecode's surrogates)
    # or control characters: XML cannot hold those
    return result.to_svg(decimals=decimals, title=None if title is None else xml_safe(title)).encode("utf-8")


def _process_umask() -> int:
    try:
        with open("/proc/self/status", encoding="ascii") as handle:
            for line in handle:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    except (OSError, ValueError, IndexError):
        pass
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


_FILE_MODE = 0o666 & ~_process_umask()


def write_atomic(path, data: bytes) -> None:
    """Write ``data`` to ``path`` through a temporary file in the same directory and ``os.replace``.

    On any failure (disk full, file-size limit, interrupt) the temporary file is removed and the error
    propagates; ``path`` then holds its previous content, or does not exist.
    """
    directory, name = os.path.split(os.fspath(path))
    handle, temporary = tempfile.mkstemp(prefix=f".{name}.", suffix=PART_SUFFIX, dir=directory or ".")
    try:
        with os.fdopen(handle, "wb") as stream:
            stream.write(data)
        os.chmod(temporary, _FILE_MODE)
        os.replace(temporary, path)
    except BaseException:
        try:
            os.unlink(temporary)
        except OSError:
            pass
        raise


def remove_partials(outputs) -> list:
    """Remove the temporary files of the given outputs (left by a killed writer); returns their paths."""
    wanted = {}
    for output in outputs:
        directory, name = os.path.split(os.fspath(output))
        wanted.setdefault(directory or ".", set()).add(name)
    removed = []
    for directory, names in wanted.items():
        try:
            entries = list(os.scandir(directory))
        except OSError:
            continue
        for entry in entries:
            if not (entry.name.startswith(".") and entry.name.endswith(PART_SUFFIX)):
                continue
            base = entry.name[1:-len(PART_SUFFIX)].rpartition(".")[0]
            if base in names:
                try:
                    os.unlink(entry.path)
                    removed.append(entry.path)
                except OSError:
                    pass
    return removed


# ---------------------------------------------------------------------------------------------------
# one file, one batch
# ---------------------------------------------------------------------------------------------------
class UnreadableImage:
    """What a worker gets for an input the calling process could not decode (a PIL image whose pixels cannot be
    read, ``batch._plan.load_images``): its file fails with ``reason``, alone."""

    def __init__(self, reason):
        self.reason = reason


def failure_reason(exc, source_name=None) -> str:
    """One line saying why a file failed (the loader's own message without a repeated file name)."""
    text = str(exc).strip()
    message = text.splitlines()[0] if text else ""
    if source_name and message.startswith(f"{source_name}: "):
        message = message[len(source_name) + 2:]
    if isinstance(exc, (ValueError, OSError)) and message:
        return message
    return f"{type(exc).__name__}: {message}" if message else type(exc).__name__


def _warning_lines(caught) -> list:
    """One line per distinct warning of a file's trace: ``Category: message`` (first line of the message)."""
    lines = []
    for warning in caught:
        text = str(warning.message).strip().splitlines()
        line = f"{warning.category.__name__}: {text[0] if text else ''}"
        if line not in lines:
            lines.append(line)
    return lines


def note_lines(result) -> list:
    """The notes of a trace that say its output is not all that was asked for, as warning lines (an SVG output
    and the command line would drop them; the other notes are fallbacks that keep the result within its
    tolerance): an all-ink image (``InkPolarityWarning``: the outline is the frame), a spent time budget
    (``TimeBudget``: boundaries left as polygons, knot rounds stopped) and the boundaries that did not converge
    otherwise (``NotConverged``: one line, how many and the first one's reason)."""
    from ..capture.trace import ALL_INK_NOTE, BUDGET_NOTE

    lines = [f"InkPolarityWarning: {note}" for note in result.notes if note.startswith(ALL_INK_NOTE)]
    lines += [f"TimeBudget: {note}" for note in result.notes if note.startswith(BUDGET_NOTE)]
    boundaries = result.stats["per_boundary"]
    unconverged = [k for k, entry in enumerate(boundaries) if entry["reason"] is not None and entry["budget"] is None]
    if unconverged:
        first = boundaries[unconverged[0]]
        lines.append(f"NotConverged: {len(unconverged)} of {len(boundaries)} boundar"
                     f"{'y' if len(boundaries) == 1 else 'ies'} did not converge: boundary {unconverged[0]} "
                     f"({first['contour_points']} points): {first['reason']}"
                     + ("; stats['per_boundary'][k]['reason'] says why for each" if len(unconverged) > 1 else ""))
    return lines


def respell(line, spelling) -> str:
    """``line`` with each ``(python, other)`` pair of ``spelling`` replaced in order (``run_batch``'s
    ``spelling``: the command line's option names for the library's argument names)."""
    for python, other in spelling:
        line = line.replace(python, other)
    return line


def _summary(stats) -> dict:
    """The record's stats: :data:`RECORD_STATS`, and ``budget_stopped``, the boundaries whose knot rounds a spent
    time budget stopped (``stats["per_boundary"][k]["budget"] == "stopped"``)."""
    summary = {name: stats[name] for name in RECORD_STATS if name in stats}
    summary["budget_stopped"] = sum(entry.get("budget") == "stopped" for entry in stats.get("per_boundary", ()))
    return summary


def trace_one(item, settings) -> dict:
    """Trace one planned file (``item``: index, source, output, title) and return its record."""
    from ..capture import trace

    started = time.perf_counter()
    source, output = item["source"], item["output"]
    record = {"index": item["index"], "status": "failed", "error": None, "input_sha256": None,
              "output_sha256": None, "stats": None, "result": None, "warnings": []}
    try:
        if isinstance(source, UnreadableImage):
            raise ValueError(source.reason)
        with warnings.catch_warnings(record=True) as caught:  # kept with the file they are about
            warnings.simplefilter("always")
            result = trace(source, **settings["trace"])  # first: the loader's messages name the file
        # the notes that qualify the output (an all-ink frame, a spent budget, unconverged boundaries), which an
        # SVG output and the command line would drop: passed on with the file's warnings
        lines = _warning_lines(caught) + note_lines(result)
        record["warnings"] = [respell(line, settings.get("spelling", ())) for line in lines]
        record["input_sha256"] = input_sha256(source)
        if output is None:
            record["result"] = result
        else:
            data = render(result, settings["format"], settings["decimals"], item["title"])
            try:
                write_atomic(output, data)
            except OSError as exc:
                raise OSError(f"cannot write {output}: {exc.strerror or exc}") from exc
            record["output_sha256"] = hashlib.sha256(data).hexdigest()
        record["stats"] = _summary(result.stats)
        record["status"] = "ok"
    except Exception as exc:  # noqa: BLE001 - one failed file never stops the batch
        name = os.fspath(source) if isinstance(source, (str, os.PathLike)) else None
        record["error"] = respell(failure_reason(exc, name), settings.get("spelling", ()))
    record["time_s"] = time.perf_counter() - started
    return record


def trace_batch(items, settings) -> list:
    """Trace a batch of planned files one after the other; one record per file, in order.

    Files not started when the run is stopped (threads, synchronous scheduler) come back as
    ``status="cancelled"``.
    """
    stop = STOP_EVENTS.get(settings.get("run"))
    records = []
    for item in items:
        if stop is not None and stop.is_set():
            records.append({"index": item["index"], "status": "cancelled", "error": "run stopped",
                            "input_sha256": None, "output_sha256": None, "stats": None, "result": None,
                            "time_s": 0.0, "warnings": []})
            continue
        records.append(trace_one(item, settings))
    return records


# ---------------------------------------------------------------------------------------------------
# local worker processes
# ---------------------------------------------------------------------------------------------------
_PR_SET_PDEATHSIG = 1


def init_worker_process(parent_pid) -> None:
    """Initializer of splinecraft's local worker processes.

    Ctrl-C goes to the parent, which decides (workers ignore SIGINT, so a Ctrl-C to the process group does
    not break a file half-way); the kernel kills the worker when its parent dies (Linux
    ``PR_SET_PDEATHSIG``), and a watchdog thread ends it when it has been re-parented (other systems).
    """
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if sys.platform.startswith("linux"):
        try:
            import ctypes

            libc = ctypes.CDLL(None, use_errno=True)
            libc.prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
        except (OSError, AttributeError):
            pass
    if os.getppid() != parent_pid:  # the parent died before the line above
        os._exit(1)

    def watch_parent():
        while os.getppid() == parent_pid:
            time.sleep(0.5)
        os._exit(1)

    threading.Thread(target=watch_parent, name="splinecraft-parent-watch", daemon=True).start()
