"""Planning a batch before anything is traced: inputs, output paths, trace settings, resume.

Everything here runs in the calling process and raises ``TypeError``/``ValueError`` naming the argument,
so a bad call fails before the first file is traced.
"""
from __future__ import annotations

import dataclasses
import glob
import hashlib
import inspect
import json
import math
import os
import stat
from dataclasses import dataclass

import numpy as np

from .._validation import blank_text, check_choice, check_positive_int, control_character
from ._work import PART_SUFFIX, UnreadableImage, file_sha256, input_sha256

FORMATS = ("svg", "json")
_GLOB_CHARACTERS = frozenset("*?[")
#: Arguments of ``trace`` that change no output, left out of the settings hash (a change does not re-trace).
UNHASHED_ARGUMENTS = ("keep_snapshots", "max_pixels")
#: Each task should run at least this long (dask's per-task overhead is ~0.2-1 ms; BENCHMARKS.md).
TARGET_TASK_S = 0.1


@dataclass
class PlannedFile:
    """One planned file: where it comes from, where it goes, and the title of its SVG."""

    index: int
    source: object          # path (str) or image array / PIL image
    label: str              # the input as shown in messages and the manifest
    output: str | None      # absolute output path, or None (results kept in memory)
    title: str | None

    def item(self) -> dict:
        """The picklable description a worker gets."""
        return {"index": self.index, "source": self.source, "output": self.output, "title": self.title}


# ---------------------------------------------------------------------------------------------------
# inputs and outputs
# ---------------------------------------------------------------------------------------------------
#: Types read as one encoded image file (PNG, JPEG, ...), as :func:`~splinecraft.capture.trace.trace` reads them.
ENCODED_IMAGE_TYPES = (bytes, bytearray, memoryview)


def _is_image_object(value) -> bool:
    return isinstance(value, np.ndarray) or type(value).__module__.startswith("PIL.")


def expand_inputs(inputs) -> list:
    """Paths, glob patterns, image arrays and encoded image bytes -> a flat list (globs expanded, sorted; order
    kept; bytearray and memoryview copied to ``bytes``, which every worker can be sent)."""
    if isinstance(inputs, np.ndarray) and inputs.dtype.kind in "USO":
        raise TypeError(f"inputs is a numpy array of dtype {inputs.dtype}, which is no image (an image array holds "
                        "numbers); for a list of paths pass inputs.tolist()")
    if isinstance(inputs, (str, os.PathLike, *ENCODED_IMAGE_TYPES)) or _is_image_object(inputs):
        inputs = [inputs]
    try:
        items = list(inputs)
    except TypeError:
        raise TypeError(f"inputs must be paths, glob patterns, image arrays or encoded image bytes (a list of "
                        f"them, or a dict {{name: image}}), got {type(inputs).__name__}") from None
    sources = []
    for position, item in enumerate(items):
        if _is_image_object(item):
            sources.append(item)
        elif isinstance(item, ENCODED_IMAGE_TYPES):
            sources.append(bytes(item))
        elif isinstance(item, (str, os.PathLike)):
            text = os.fspath(item)
            if not isinstance(text, str):
                raise TypeError(f"inputs[{position}] must be a text path, got bytes")
            if _GLOB_CHARACTERS & set(text) and not os.path.exists(text):
                matches = sorted(path for path in glob.glob(text, recursive=True) if os.path.isfile(path))
                if not matches:
                    raise ValueError(f"inputs[{position}]: the pattern {text!r} matches no file")
                sources.extend(matches)
            else:
                sources.append(text)
        else:
            raise TypeError(f"inputs[{position}] must be a path, a glob pattern, an image array or encoded image "
                            f"bytes, got {type(item).__name__}")
    if not sources:
        raise ValueError("inputs is empty: give at least one path, glob pattern, image array or encoded image")
    return sources


def named_inputs(inputs) -> tuple:
    """A mapping ``{name: image}`` -> ``(names, sources)`` in the mapping's order. Each key is a name (a ``str`` that
    can name a file: not blank, no directory separator or control character, not ``.`` or ``..``); each value one
    image: a path (taken literally, never as a glob pattern), an image array, a PIL image or encoded image bytes
    (``bytearray`` and ``memoryview`` copied to ``bytes``)."""
    names, sources = [], []
    for name, item in inputs.items():
        if not isinstance(name, str):
            raise TypeError(f"inputs keys must be names (str), got {name!r} ({type(name).__name__}): a mapping "
                            "of inputs is {name: image}")
        name = str(name)  # plain text: np.str_ keys (from a numpy array of names) showed as np.str_('a')
        separators = {"/", os.sep, os.altsep} - {None}
        control = control_character(name)
        if (blank_text(name) or name in (".", "..") or any(separator in name for separator in separators)
                or control):
            why = f" (U+{control[1]:04X} at index {control[0]})" if control else ""
            raise ValueError(f"inputs key {name!r} is not a name{why}: a key names its output NAME.svg, so it must "
                             "hold more than white space, not be '.' or '..', and hold no directory separator or "
                             "control character (NUL, tab, newline)")
        if _is_image_object(item):
            sources.append(item)
        elif isinstance(item, ENCODED_IMAGE_TYPES):
            sources.append(bytes(item))
        elif isinstance(item, (str, os.PathLike)) and isinstance(os.fspath(item), str):
            sources.append(os.fspath(item))
        else:
            raise TypeError(f"inputs[{name!r}] must be a path, an image array, a PIL image or encoded image bytes, "
                            f"got {type(item).__name__} (one image per name)")
        names.append(name)
    if not sources:
        raise ValueError("inputs is empty: give at least one path, glob pattern, image array or encoded image")
    return names, sources


def plan_directory(sources, output_dir, fmt, names=None) -> list:
    """One job per source; outputs ``output_dir/NAME.fmt`` (``image-00003`` for arrays and bytes: the input's
    position; with ``names``, one per source, that name: also the label and the SVG title), or none. One PIL image
    of several frames given for two inputs is refused (:func:`_refuse_shared_frames`)."""
    width = max(5, len(str(len(sources) - 1)))
    jobs, seen, images = [], {}, {}
    for index, source in enumerate(sources):
        if names is not None:
            stem = label = title = names[index]
        elif isinstance(source, str):
            stem, label, title = os.path.splitext(os.path.basename(source))[0], source, os.path.basename(source)
        else:
            kind = "bytes" if isinstance(source, bytes) else "image"
            stem, label, title = f"image-{index:0{width}d}", f"<{kind} {index}>", None
        if type(source).__module__.startswith("PIL."):
            _refuse_shared_frames(images.setdefault(id(source), (source, label)), source, label)
        output = None
        if output_dir is not None:
            name = f"{stem}.{fmt}"
            if name in seen:
                raise ValueError(f"inputs {seen[name]} and {label} would both be written to {name} in output_dir")
            seen[name] = label
            output = os.path.abspath(os.path.join(output_dir, name))
        jobs.append(PlannedFile(index=index, source=source, label=label, output=output, title=title))
    return jobs


def _refuse_shared_frames(first, source, label) -> None:
    """``ValueError`` when ``source``, a PIL image of several frames, was given before (``first``: that input's
    image and label): a PIL image is traced at the frame it is at when its turn comes, so the frames of one image
    seeked in a loop would all be traced at its last frame."""
    image, first_label = first
    if image is not source or first_label == label or getattr(source, "n_frames", 1) <= 1:
        return
    raise ValueError(f"inputs {first_label} and {label} are the same PIL image object, a file of {source.n_frames} "
                     f"frames now at frame {source.tell()}: a PIL image is traced at the frame it is at when it is "
                     "traced, so both would be that frame; give each frame its own image (img.seek(k), then "
                     "img.copy())")


def read_pipes(plan) -> list:
    """The plan with every input path that is a pipe (the shell's ``<(...)``, ``/dev/stdin``) replaced by its
    bytes, read once here: a pipe can be read only once, and the resume check hashes the input before it is
    traced (the trace then read an empty pipe: "not an image file"). Label, output and title stay the path's.
    A pipe that cannot be read stays a path and fails as its file."""
    from ..capture.image import read_pipe

    planned = []
    for job in plan:
        if isinstance(job.source, str):
            try:
                piped = read_pipe(job.source)
            except OSError:  # a pipe that cannot be read stays a path and fails as its file
                piped = None
            if piped is not None:
                job = dataclasses.replace(job, source=piped)
        planned.append(job)
    return planned


def load_images(plan, max_pixels) -> list:
    """The plan with the pixels of every PIL image input decoded here, in the calling process: PIL reads them from
    the image's file when first asked, and an image sent to a worker process is pickled, which reads them there;
    one that cannot be read (its file closed before they were loaded, truncated data) failed the whole task it
    was sent in, the good images beside it too, or a dask run. Such an input becomes an
    :class:`~splinecraft.batch._work.UnreadableImage` that fails alone, with the loader's reason. An image of
    more than ``max_pixels`` pixels (trace's cap) is left undecoded: its trace refuses it from its size."""
    from ..capture.image import load_pil_pixels

    planned = []
    for job in plan:
        source = job.source
        if type(source).__module__.startswith("PIL.") and int(source.width) * int(source.height) <= max_pixels:
            try:
                load_pil_pixels(job.source, "PIL image")
            except ValueError as exc:
                job = dataclasses.replace(job, source=UnreadableImage(str(exc)))
        planned.append(job)
    return planned


def _identity(path):
    try:
        status = os.stat(path)
    except OSError:
        return None
    return status.st_dev, status.st_ino


def refuse_overwriting_inputs(jobs, manifest_path) -> None:
    """``ValueError`` when an output or the manifest is also an input (same path after symlinks, or the
    same file through a hard link): it would be overwritten."""
    by_path, by_identity = {}, {}
    for job in jobs:
        if isinstance(job.source, str):
            by_path[os.path.realpath(job.source)] = job.label
            identity = _identity(job.source)
            if identity is not None:
                by_identity[identity] = job.label
    if not by_path:
        return
    targets = [(job.output, "output") for job in jobs if job.output is not None]
    if manifest_path is not None:
        targets.append((manifest_path, "manifest"))
    for target, what in targets:
        label = by_path.get(os.path.realpath(target)) or by_identity.get(_identity(target))
        if label is not None:
            raise ValueError(f"{what} {target} is also an input ({label}); it would be overwritten: "
                             "choose another output")


def refuse_manifest_as_output(jobs, manifest_path) -> None:
    """``ValueError`` when the manifest is also an output (same path after symlinks, or the same file through a
    hard link): the output would be written and the manifest's lines appended to it."""
    if manifest_path is None:
        return
    real, identity = os.path.realpath(manifest_path), _identity(manifest_path)
    for job in jobs:
        if job.output is not None and (os.path.realpath(job.output) == real
                                       or (identity is not None and _identity(job.output) == identity)):
            raise ValueError(f"manifest {manifest_path} is also the output of {job.label}; the manifest's lines "
                             "would be appended to that output: choose another manifest")


#: Kinds of file that an output or the manifest must not be (they are written through a temporary file renamed
#: over them, which would replace the pipe or the device node with a regular file), by ``stat`` test.
_SPECIAL_FILES = ((stat.S_ISFIFO, "a named pipe (FIFO)"), (stat.S_ISCHR, "a character device"),
                  (stat.S_ISBLK, "a block device"), (stat.S_ISSOCK, "a socket"))


def refuse_special_files(jobs, manifest_path) -> None:
    """``ValueError`` when an output or the manifest exists and is a named pipe, a device or a socket (after
    symlinks: ``/dev/stdout``): outputs and the manifest are written through a temporary file renamed over them,
    which would replace it by a regular file, and the resume check would read it (a pipe without a writer
    blocks)."""
    targets = [(job.output, "output") for job in jobs if job.output is not None]
    if manifest_path is not None:
        targets.append((manifest_path, "manifest"))
    for target, what in targets:
        try:
            mode = os.stat(target).st_mode
        except OSError:
            continue
        for test, kind in _SPECIAL_FILES:
            if test(mode):
                raise ValueError(f"{what} {target} is {kind}, not a regular file: it would be replaced by a "
                                 "regular file (outputs are written to a temporary file renamed over theirs); "
                                 "give a file path (on the command line, -o - writes to stdout)")


def directory_ignores_case(directory, name) -> bool:
    """Whether the file system of ``directory`` finds its file ``name`` (just created) also under that name with
    the case of its letters swapped (the usual file systems of macOS and Windows)."""
    return os.path.exists(os.path.join(directory, name.swapcase()))


def prepare_directories(jobs, manifest_path) -> None:
    """Create the output directories and check that a file can be created in each (before any tracing); in a
    directory that ignores case, two outputs whose names differ only in case are refused (one file there)."""
    directories = {os.path.dirname(job.output) for job in jobs if job.output is not None}
    if manifest_path is not None:
        directories.add(os.path.dirname(manifest_path))
    for directory in sorted(directories):
        if os.path.exists(directory) and not os.path.isdir(directory):
            raise ValueError(f"output directory {directory} exists and is not a directory")
        try:
            os.makedirs(directory, exist_ok=True)
            name = f".write-check.{os.getpid()}{PART_SUFFIX}"
            probe = os.path.join(directory, name)
            with open(probe, "wb"):
                pass
            try:
                ignores_case = directory_ignores_case(directory, name)
            finally:
                os.unlink(probe)
        except OSError as exc:
            raise OSError(exc.errno, f"output directory {directory} is not writable: "
                                     f"{exc.strerror or exc}") from exc
        if ignores_case:
            _refuse_case_collisions([job for job in jobs if job.output is not None
                                     and os.path.dirname(job.output) == directory], directory)


def _refuse_case_collisions(jobs, directory) -> None:
    seen = {}
    for job in jobs:
        name = os.path.basename(job.output)
        first = seen.setdefault(name.casefold(), job)
        if first is not job:
            raise ValueError(f"inputs {first.label} and {job.label} would both be written to "
                             f"{os.path.basename(first.output)} and {name}, one file in output directory "
                             f"{directory}, which ignores case: rename one")


# ---------------------------------------------------------------------------------------------------
# trace settings
# ---------------------------------------------------------------------------------------------------
def trace_settings(trace_params) -> tuple:
    """``(keyword arguments for trace, their hash)``; unknown names raise ``TypeError``.

    The hash covers every argument of :func:`~splinecraft.capture.trace.trace` with its default filled in
    (so spelling out a default does not re-trace), except those that change no output: ``keep_snapshots``,
    and ``max_pixels`` (an image it refuses fails, and is not skipped by a later run).
    """
    from .. import __version__
    from ..capture import trace

    signature = inspect.signature(trace)
    try:
        bound = signature.bind(None, **trace_params)
    except TypeError as exc:
        raise TypeError(f"trace_many: {exc} (the keyword arguments after the batch options go to "
                        "splinecraft.trace)") from None
    bound.apply_defaults()
    arguments = dict(bound.arguments)
    arguments.pop(next(iter(signature.parameters)))  # the image
    if "keep_snapshots" not in trace_params:
        arguments["keep_snapshots"] = False  # a batch writes outputs: snapshots are not needed
    hashed = {name: value for name, value in arguments.items() if name not in UNHASHED_ARGUMENTS}
    text = json.dumps({"trace": hashed, "splinecraft": __version__}, sort_keys=True, default=repr)
    return arguments, hashlib.sha256(text.encode()).hexdigest()


def check_trace_arguments(arguments) -> None:
    """Let :func:`trace` check its own arguments once, before any file: it traces an empty image with
    them and with its defaults; a different error than the defaults' names the bad argument."""
    from ..capture import trace

    empty = np.zeros((0, 0), dtype=np.uint8)

    def error_of(**kwargs):
        try:
            trace(empty, **kwargs)
        except (TypeError, ValueError) as exc:
            return exc
        return None

    baseline, error = error_of(), error_of(**arguments)
    if error is not None and (baseline is None or (type(error), str(error)) != (type(baseline), str(baseline))):
        raise type(error)(str(error)) from None


def params_sha256(settings_hash, fmt, decimals) -> str:
    """Hash of everything that decides an output's bytes, besides the input."""
    text = f"{settings_hash}|{fmt}|{decimals}"
    return hashlib.sha256(text.encode()).hexdigest()


def check_batch_size(batch_size):
    """``"auto"`` or an int >= 1."""
    if isinstance(batch_size, str):
        return check_choice(batch_size, "batch_size", ("auto",))
    return check_positive_int(batch_size, "batch_size")


def auto_batch_size(seconds_per_file, remaining, workers) -> int:
    """Files per task so that a task runs about :data:`TARGET_TASK_S`, yet every worker gets >= 4 tasks."""
    seconds_per_file = max(float(seconds_per_file), 1e-4)
    size = math.ceil(TARGET_TASK_S / seconds_per_file)
    balance = max(1, remaining // (4 * max(1, workers)))
    return max(1, min(size, balance))


# ---------------------------------------------------------------------------------------------------
# resume
# ---------------------------------------------------------------------------------------------------
def is_finished(job, entry, params_hash) -> bool:
    """The manifest's line says this job's output is done, and input, settings and output still match."""
    if not entry or entry.get("status") != "ok" or entry.get("params_sha256") != params_hash:
        return False
    if isinstance(job.source, UnreadableImage):
        return False
    if job.title is not None and os.path.basename(str(entry.get("input", ""))) != job.title:
        return False  # the SVG title is the input's file name
    try:
        return (file_sha256(job.output) == entry.get("output_sha256")
                and input_sha256(job.source) == entry.get("input_sha256"))
    except OSError:
        return False
