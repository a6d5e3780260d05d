"""The resume manifest: ``splinecraft-manifest.jsonl``, one JSON line per output file.

Each line records one traced file (README, "Many bitmaps")::

    {"output": "a.svg", "input": "scans/a.png", "status": "ok", "input_sha256": "...",
     "params_sha256": "...", "output_sha256": "...", "error": null, "time_s": 0.021,
     "stats": {...}, "finished": "2026-01-01T12:00:00Z", "splinecraft": "0.1.0"}

``output`` is relative to the manifest's directory, so a traced folder can be moved with its manifest.
Lines are appended (and flushed) as files finish, so a killed run keeps what it had finished; at the end of a
run the file is rewritten atomically with the newest line per output (one line per file). A line torn by a
run killed while appending (the start of a JSON object) is ignored; a file with any other line that is not a
manifest line (notes, an SVG, another program's JSON) is refused, not rewritten.
"""
from __future__ import annotations

import json
import os

from ._work import write_atomic

#: File name of the manifest in an output directory.
MANIFEST_NAME = "splinecraft-manifest.jsonl"


class Manifest:
    """Read, append to and compact one manifest file."""

    def __init__(self, path):
        self.path = os.path.abspath(os.fspath(path))
        self.directory = os.path.dirname(self.path)
        self.entries: dict = {}
        self.ignored_lines = 0
        self._stream = None

    def key(self, output) -> str:
        """The ``output`` field of a line: the output's path relative to the manifest's directory."""
        return os.path.relpath(os.path.abspath(os.fspath(output)), self.directory)

    def load(self) -> dict:
        """Read every line; the newest line of each output wins. A missing file is an empty manifest. A line torn by
        a run killed while appending (the start of a JSON object) is ignored; a file with any other line is not a
        manifest, a ``ValueError`` (the run would rewrite it with its own lines: its content would be lost)."""
        self.entries, self.ignored_lines = {}, 0
        try:
            with open(self.path, encoding="utf-8") as handle:
                lines = handle.read().splitlines()
        except (FileNotFoundError, NotADirectoryError):  # (a folder on its path that is a file: said when it is made)
            return self.entries
        except UnicodeDecodeError as exc:
            raise ValueError(f"manifest {self.path} is not a splinecraft manifest (not UTF-8 text)") from exc
        for number, line in enumerate(lines, 1):
            if not line.strip():
                continue
            try:
                entry = json.loads(line)
            except ValueError:
                entry = None
                if line.lstrip().startswith("{"):  # torn: a run killed while appending it
                    self.ignored_lines += 1
                    continue
            if not isinstance(entry, dict) or not isinstance(entry.get("output"), str):
                shown = line if len(line) <= 60 else line[:57] + "..."
                raise ValueError(f"manifest {self.path} is not a splinecraft manifest (line {number}: {shown!r} is "
                                 "no manifest line); it would be rewritten with this run's lines: give a new file "
                                 f"name, or leave the manifest out (output_dir/{MANIFEST_NAME})")
            self.entries[entry["output"]] = entry
        return self.entries

    def append(self, entries) -> None:
        """Append lines and flush them (the file is opened on first use)."""
        if self._stream is None:
            self._stream = open(self.path, "a", encoding="utf-8")
        text = "".join(json.dumps(entry, allow_nan=False, sort_keys=True) + "\n" for entry in entries)
        for entry in entries:
            self.entries[entry["output"]] = entry
        self._stream.write(text)
        self._stream.flush()

    def close(self) -> None:
        if self._stream is not None:
            stream, self._stream = self._stream, None
            stream.close()

    def compact(self) -> None:
        """Rewrite the file atomically with one line per output (the newest)."""
        self.close()
        if not self.entries and not os.path.exists(self.path):
            return
        text = "".join(json.dumps(entry, allow_nan=False, sort_keys=True) + "\n" for entry in self.entries.values())
        write_atomic(self.path, text.encode("utf-8"))
