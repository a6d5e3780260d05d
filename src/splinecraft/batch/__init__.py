"""Batch tracing: :func:`trace_many` traces many bitmaps, on one machine or on a dask cluster.

Every file goes through the same public pipeline as :func:`splinecraft.trace` (docs/capture.md), and every
scheduler writes the same bytes: ``TraceResult.to_svg(decimals=..., title=<input file name>)``, or
``TraceResult.to_dict()`` as JSON without the wall-clock fields ``stats["time_s"]``,
``stats["time_breakdown"]`` and ``stats["time_per_boundary_s"]`` (a file's time is in its record and in the manifest instead). Outputs appear
atomically (temporary file in the same directory, then ``os.replace``); a failed file never stops the
batch. The manifest (:mod:`splinecraft.batch._manifest`) makes a second run skip what is finished.

Work is grouped into tasks of several files, so that each task runs for at least ~100 ms
(:data:`TARGET_TASK_S`) against dask's per-task overhead of ~0.2-1 ms: with ``batch_size="auto"`` the first
file of each worker is traced alone, their median time sets the task size for the rest. The figures and the
cost model for a million files are in BENCHMARKS.md ("Batch tracing").
"""
from __future__ import annotations

import os
import statistics
import sys
import time
import uuid
from collections.abc import Mapping
from dataclasses import asdict, dataclass, field

from .._validation import blank_text, check_bool, check_choice, check_int
from ..spline.svg import MAX_DECIMALS
from ._manifest import MANIFEST_NAME, Manifest
from ._plan import (FORMATS, TARGET_TASK_S, auto_batch_size, check_batch_size, check_trace_arguments,
                    expand_inputs, is_finished, load_images, named_inputs, params_sha256, plan_directory,
                    prepare_directories, read_pipes, refuse_manifest_as_output, refuse_overwriting_inputs,
                    refuse_special_files, trace_settings)
from ._schedulers import LOCAL_SCHEDULERS, cpu_count, make_runner
from ._work import remove_partials, render

__all__ = ["trace_many", "FileRecord", "BatchResult", "MANIFEST_NAME", "LOCAL_SCHEDULERS", "TARGET_TASK_S",
           "cpu_count", "render"]


@dataclass
class FileRecord:
    """What happened to one input.

    ``status`` is ``"ok"`` (traced and written), ``"skipped"`` (finished by an earlier run: the manifest's
    hashes of input, settings and output still match), ``"failed"`` (``error`` says why, in one line) or
    ``"cancelled"`` (the run was stopped before this file). ``stats`` holds the main columns of
    ``TraceResult.stats`` (and ``budget_stopped``: the boundaries whose knot rounds a spent time budget
    stopped); ``result`` is the :class:`~splinecraft.capture.trace.TraceResult` itself when
    ``output_dir`` is ``None``. ``warnings``: the warnings its trace gave (``"Category: message"``, e.g. an
    ink polarity that looks inverted), kept with the file instead of printed by the worker, and the notes of
    its trace that say the output is not all that was asked for (``batch._work.note_lines``):
    ``"InkPolarityWarning: every pixel is ink ..."``, ``"TimeBudget: time budget of ..."`` (boundaries left as
    polygons, knot rounds stopped), ``"NotConverged: N of M boundaries did not converge: ..."``.
    """

    input: str
    output: str | None
    status: str
    error: str | None = None
    time_s: float = 0.0
    stats: dict | None = None
    input_sha256: str | None = None
    output_sha256: str | None = None
    index: int = 0
    result: object = field(default=None, repr=False)
    warnings: list = field(default_factory=list)

    def to_dict(self) -> dict:
        """The record without ``result`` (JSON-able)."""
        data = asdict(self)
        data.pop("result")
        return data


class BatchResult(list):
    """The :class:`FileRecord` of every input, in input order (``manifest_error``: why the manifest could
    not be written, else ``None``)."""

    manifest_error = None

    @property
    def counts(self) -> dict:
        """Number of files per status."""
        counts = {}
        for record in self:
            counts[record.status] = counts.get(record.status, 0) + 1
        return counts

    @property
    def failed(self) -> list:
        return [record for record in self if record.status == "failed"]

    def to_dataframe(self):
        """The records as a ``pandas.DataFrame`` (one row per input; stats flattened to columns)."""
        try:
            import pandas
        except ImportError:
            raise ImportError("BatchResult.to_dataframe needs pandas: pip install pandas") from None
        rows = []
        for record in self:
            row = record.to_dict()
            stats = row.pop("stats") or {}
            row.update({f"stats.{name}": value for name, value in stats.items()})
            rows.append(row)
        return pandas.DataFrame(rows)

    def __repr__(self) -> str:
        counts = ", ".join(f"{status}={count}" for status, count in sorted(self.counts.items()))
        return f"BatchResult({len(self)} files: {counts})"


def trace_many(inputs, output_dir=None, *, scheduler=None, jobs=None, batch_size="auto", resume=True,
               format="svg", manifest=None, decimals=4, progress=None, on_record=None,
               **trace_params) -> BatchResult:
    """Trace many bitmaps with :func:`splinecraft.trace`, write one output each, and resume where a run stopped.

    Parameters
    ----------
    inputs : path, glob pattern, image array, encoded image bytes, a list of them, or a mapping {name: image}
        Globs (``"scans/**/*.png"``) expand to the sorted matching files; arrays and PIL images are traced
        as given (a PIL image's pixels are decoded in the calling process before the run; one that cannot be read
        fails alone), and ``bytes`` (``bytearray``, ``memoryview``) as the encoded image file they hold, as
        :func:`splinecraft.trace` reads them (never as a file name); both are named by their position
        (outputs ``image-00000.svg``, ..., records ``<image 0>`` / ``<bytes 0>``). A mapping (a ``dict``)
        names its inputs by its keys, in its order: ``{"logo": array, "page-1": "scans/p1.png"}`` gives the
        outputs ``logo.svg`` and ``page-1.svg`` (titled and recorded as ``logo``, ``page-1``); each value is one
        image (a path is taken literally, never as a glob pattern), each key a name that can name a file (a
        non-empty ``str`` without a directory separator).
    output_dir : path, optional
        Where ``NAME.svg`` (``.json``) goes for input ``NAME.png``; created if needed (not empty: ``"."`` is the
        current directory). ``None``: nothing is written, each record carries its ``TraceResult`` (no manifest,
        no resume).
    scheduler : None, str or distributed.Client
        ``None``: in this process, one file after the other (``jobs > 1``: that many local worker
        processes, no dask needed). ``"threads"``, ``"processes"``, ``"synchronous"``: dask's local
        schedulers (``jobs`` workers, default one per CPU). A ``dask.distributed.Client`` or a scheduler
        address such as ``"tcp://host:8786"``: that cluster (its workers must see the same paths). Dask is
        the optional extra ``pip install 'splinecraft[dask]'``. BENCHMARKS.md compares them.
    jobs : int >= 0, optional
        Local workers; ``0`` is one per CPU (as ``--jobs 0`` on the command line); more than the CPU count is
        capped at it with a ``RuntimeWarning``. The workers are spawned processes, which import the calling
        script again: in a script, call with ``jobs > 1`` (or ``scheduler="processes"``) under
        ``if __name__ == "__main__":`` (a notebook needs nothing).
    batch_size : "auto" or int
        Files per task ("auto": each task runs about ``TARGET_TASK_S`` = 0.1 s).
    resume : bool
        Skip files whose manifest line shows a finished output with the same input, settings and output
        hashes. ``False`` traces everything again (the manifest is still written).
    format : {"svg", "json"}
        Output format (see the module text for the exact bytes).
    manifest : path, optional
        The manifest file; default ``output_dir/splinecraft-manifest.jsonl``. Only with an ``output_dir``.
    decimals : int in [0, 64] (``spline.svg.MAX_DECIMALS``) or None
        Decimal places of SVG coordinates (``TraceResult.to_svg``).
    progress : bool, optional
        Show a progress bar (tqdm; a widget in Jupyter). ``None``: when stderr is a terminal or in Jupyter.
    on_record : callable, optional
        Called with each :class:`FileRecord` as its file finishes (in the calling thread).
    **trace_params
        Keyword arguments of :func:`splinecraft.trace` (``epsilon``, ``method``, ...); ``keep_snapshots``
        defaults to ``False`` here.

    Returns
    -------
    BatchResult
        One :class:`FileRecord` per input, in input order; ``.to_dataframe()`` with pandas. The warnings of
        each file's trace are in its record's ``warnings`` (and its manifest line), not printed.

    Raises
    ------
    TypeError, ValueError
        Bad arguments (named), an output that is also an input, a manifest that is also an output, an output or
        manifest that is a named pipe or a device (``/dev/null``), two inputs with the same output name (or names
        that differ only in case, in an output directory that ignores case: macOS, Windows), one PIL image of
        several frames given for several inputs (each is traced at the frame it is at when traced: pass
        ``img.copy()`` after each ``img.seek(k)``).
    OSError
        An output directory that cannot be created or written. ``ConnectionError``: no dask scheduler
        answers at the address (within 5 s).
    ImportError
        A dask scheduler without dask installed (the message says how to install it).
    """
    check_choice(format, "format", FORMATS)
    if isinstance(inputs, Mapping):
        names, sources = named_inputs(inputs)
    else:
        names, sources = None, expand_inputs(inputs)
    if output_dir is not None:
        output_dir = os.fspath(output_dir)
        if blank_text(output_dir):
            raise ValueError(f"output_dir is {blank_text(output_dir)}: give a directory ('.' for the current one), or "
                             "None to keep the results in memory")
    plan = plan_directory(sources, output_dir, format, names)
    if manifest is None and output_dir is not None:
        manifest = os.path.join(output_dir, MANIFEST_NAME)
    return run_batch(plan, manifest=manifest, scheduler=scheduler, jobs=jobs, batch_size=batch_size,
                     resume=resume, format=format, decimals=decimals, progress=progress, on_record=on_record,
                     trace_params=trace_params)


class _Run:
    """The bookkeeping of one run: records, manifest lines, progress bar, callback."""

    def __init__(self, plan, manifest, params_hash, bar, on_record):
        self.planned = {planned.index: planned for planned in plan}
        self.records = {}
        self.manifest, self.params_hash, self.bar, self.on_record = manifest, params_hash, bar, on_record
        self.manifest_error = None

    def add(self, record):
        self.records[record.index] = record
        if self.bar is not None:
            self.bar.update(1)
        if self.on_record is not None:
            self.on_record(record)

    def finished(self, raw_records):
        """Records of a finished batch (worker dicts) -> FileRecords, manifest lines, progress."""
        records, lines = [], []
        for raw in raw_records:
            job = self.planned[raw["index"]]
            record = FileRecord(input=job.label, output=job.output, status=raw["status"], error=raw["error"],
                                time_s=raw["time_s"], stats=raw["stats"], input_sha256=raw["input_sha256"],
                                output_sha256=raw["output_sha256"], index=job.index, result=raw["result"],
                                warnings=list(raw.get("warnings", ())))
            records.append(record)
            if self.manifest is not None and record.status in ("ok", "failed"):
                lines.append(self._line(record))
        if lines:
            try:
                self.manifest.append(lines)
            except OSError as exc:
                self.manifest_error = self.manifest_error or f"cannot write manifest {self.manifest.path}: {exc}"
        for record in records:
            self.add(record)

    def _line(self, record) -> dict:
        from .. import __version__

        return {"output": self.manifest.key(record.output), "input": record.input, "status": record.status,
                "input_sha256": record.input_sha256, "params_sha256": self.params_hash,
                "output_sha256": record.output_sha256, "error": record.error, "warnings": record.warnings,
                "time_s": round(record.time_s, 6),
                "stats": record.stats, "finished": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
                "splinecraft": __version__}

    def result(self) -> BatchResult:
        return BatchResult(self.records[index] for index in sorted(self.records))


def _progress_bar(total, initial, enabled):
    if enabled is None:
        enabled = sys.stderr.isatty() or _in_jupyter()
    if not enabled or total == 0:
        return None
    if _in_jupyter():
        from tqdm.auto import tqdm
    else:
        from tqdm import tqdm
    return tqdm(total=total, initial=initial, unit="file", desc="tracing", file=sys.stderr, dynamic_ncols=True)


def _in_jupyter() -> bool:
    shell = sys.modules.get("IPython")
    shell = shell.get_ipython() if shell is not None and hasattr(shell, "get_ipython") else None
    return shell is not None and hasattr(shell, "kernel")


def run_batch(plan, *, manifest=None, scheduler=None, jobs=None, batch_size="auto", resume=True,
              format="svg", decimals=4, progress=None, on_record=None, trace_params=None, spelling=()):
    """Trace planned files (:class:`~splinecraft.batch._plan.PlannedFile`, each with its own output path):
    the body of :func:`trace_many`, also used by the command line for explicit output file names.

    ``spelling``: ``(python, other)`` text pairs replaced, in order, in each file's warning and error lines
    (records and manifest), so that the command line's messages name its options (``--invert`` where
    :func:`splinecraft.trace` says ``invert=True``); :func:`trace_many` keeps the library's words."""
    check_choice(format, "format", FORMATS)
    batch_size = check_batch_size(batch_size)
    decimals = None if decimals is None else check_int(decimals, "decimals", minimum=0, maximum=MAX_DECIMALS)
    resume = check_bool(resume, "resume")
    progress = None if progress is None else check_bool(progress, "progress")
    if on_record is not None and not callable(on_record):
        raise TypeError(f"on_record must be callable, got {type(on_record).__name__}")
    arguments, settings_hash = trace_settings(trace_params or {})
    check_trace_arguments(arguments)
    writes = any(planned.output is not None for planned in plan)
    if manifest is not None and blank_text(os.fspath(manifest)):
        raise ValueError(f"manifest is {blank_text(os.fspath(manifest))}: give a file name, or None for the default "
                         f"(output_dir/{MANIFEST_NAME})")
    if manifest is not None and not writes:
        raise ValueError(f"manifest {os.fspath(manifest)} is given, but output_dir is None: nothing is written, so "
                         "there is nothing to record or resume; give an output_dir, or leave manifest out")
    manifest_path = os.path.abspath(os.fspath(manifest)) if manifest is not None and writes else None
    if manifest_path is not None and os.path.isdir(manifest_path):
        raise ValueError(f"manifest {manifest_path!r} is a directory: give the manifest's file name, e.g. "
                         f"{os.path.join(manifest_path, MANIFEST_NAME)!r}")
    refuse_overwriting_inputs(plan, manifest_path)
    refuse_manifest_as_output(plan, manifest_path)
    refuse_special_files(plan, manifest_path)
    ledger = Manifest(manifest_path) if manifest_path is not None else None
    entries = ledger.load() if ledger is not None else {}  # before anything is created: it may be refused
    runner = make_runner(scheduler, jobs, len(plan))
    try:
        prepare_directories(plan, manifest_path)
    except BaseException:
        runner.close()
        raise
    params_hash = params_sha256(settings_hash, format, decimals)
    plan = read_pipes(plan)  # read once: hashed for resume and traced from the same bytes
    plan = load_images(plan, arguments["max_pixels"])  # PIL images decoded here: one that cannot be fails alone

    skipped, pending = [], []
    for job in plan:
        entry = entries.get(ledger.key(job.output)) if ledger is not None and job.output is not None else None
        (skipped if resume and is_finished(job, entry, params_hash) else pending).append((job, entry))
    outputs = [planned.output for planned in plan if planned.output is not None]
    remove_partials(outputs)

    bar = _progress_bar(len(plan), 0, progress)
    run = _Run(plan, ledger, params_hash, bar, on_record)
    spelling = tuple((str(python), str(other)) for python, other in spelling)
    settings = {"trace": arguments, "format": format, "decimals": decimals, "run": uuid.uuid4().hex,
                "spelling": spelling}
    completed = False
    try:
        for job, entry in skipped:
            run.add(FileRecord(input=job.label, output=job.output, status="skipped", time_s=0.0,
                               stats=entry.get("stats"), input_sha256=entry.get("input_sha256"),
                               output_sha256=entry.get("output_sha256"), index=job.index))
        _trace_pending([job for job, _ in pending], runner, batch_size, settings, run.finished)
        completed = True
    finally:
        if not completed:
            runner.stop()
        runner.close()
        remove_partials(outputs)
        if ledger is not None:
            try:
                ledger.compact()
            except OSError as exc:
                run.manifest_error = run.manifest_error or f"cannot write manifest {ledger.path}: {exc}"
        if bar is not None:
            bar.close()
    result = run.result()
    result.manifest_error = run.manifest_error
    return result


def _trace_pending(plan, runner, batch_size, settings, on_done):
    """Batches of the planned files to the runner; with ``"auto"``, one file per worker first to time them."""
    items = [planned.item() for planned in plan]
    if runner.workers <= 1 and runner.name in ("serial", "synchronous"):
        size = 1 if batch_size == "auto" else batch_size
        runner.run([items[i:i + size] for i in range(0, len(items), size)], settings, on_done)
        return
    if batch_size == "auto":
        probes, items = items[:runner.workers], items[runner.workers:]
        timings = []

        def timed(records):
            timings.extend(r["time_s"] for r in records if r["status"] == "ok")
            on_done(records)

        runner.run([[item] for item in probes], settings, timed)
        if not items:
            return
        batch_size = auto_batch_size(statistics.median(timings) if timings else 0.0, len(items), runner.workers)
    runner.run([items[i:i + batch_size] for i in range(0, len(items), batch_size)], settings, on_done)
