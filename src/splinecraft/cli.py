"""Command line: ``splinecraft trace IN [IN ...] -o OUT`` (outline capture to SVG or JSON).

Examples
--------
::

    splinecraft trace glyph.png -o glyph.svg
    splinecraft trace scans/*.png -o traced/ --epsilon 1 --method fuzzy --jobs 4
    splinecraft trace scans/*.png -o traced/ --scheduler tcp://10.0.0.5:8786   # a dask cluster
    splinecraft trace 'scans/**/*.png' -o traced/     # a quoted pattern: expanded here, as trace_many does
    splinecraft trace logo.png -o - --format json          # JSON to stdout
    splinecraft trace glyph.png -o glyph.svg --fit-param merge_tolerance=0   # fit_params: the thesis's C2 fit
    splinecraft --version

``OUT`` is a file for one input (``-`` = stdout) and a directory for several (created if needed; each
input ``NAME.ext`` becomes ``OUT/NAME.svg`` or ``.json``). The format follows ``--format``, else the
suffix of a single output file, else SVG (a single output named like an image, ``-o out.png``, or like the
other format than ``--format`` asks for, is refused). An output that is also an input is refused, and so, before
anything is traced, an empty ``OUT`` and an ``OUT`` named like a file (``.svg``, ``.json``) for several
inputs, unless it is an existing directory (``OUT/`` asks for the directory), and ``-o -`` with an option of
file outputs (``--manifest``, ``--jobs``, ``--scheduler``, ``--batch-size``: stdout gets one input traced in
this process, with no manifest). Files are traced by
:func:`splinecraft.batch.run_batch`, the body of ``splinecraft.trace_many``: outputs appear atomically (no
partial file, even when a write fails), and a directory gets a manifest
(``OUT/splinecraft-manifest.jsonl``, or ``--manifest``) so that a second run skips finished files
(``--no-resume`` traces them again). Over several files a tqdm progress bar is drawn on stderr when it is
a terminal (never with ``--quiet``). ``--max-pixels N`` refuses (that file fails) an image of more than N
pixels, read from its header before anything is decoded (default ``capture.image.MAX_PIXELS`` = 10^8: a
decompression bomb costs nothing); it changes no output, so a rerun with another N still skips finished
files. A file that fails gets one line ``splinecraft: FILE: reason`` on
stderr while the others still finish. Every warning of a file's trace gets a line
``splinecraft: FILE: warning: Category: message``, also with ``--quiet``, and is kept in its manifest line: the
Python warnings it gave (an ink polarity that looks inverted, a multi-frame file of which the first frame was
traced) and the notes that say its output is not all that was asked for (``batch._work.note_lines``: every
pixel ink, boundaries that did not converge). A file whose ``--time-budget`` ran out gets a line saying how many
of its boundaries were kept as the polygons of their contours, and one for knot rounds the budget stopped (not
with ``--quiet``; the manifest keeps the note); ``-v`` counts the polygons apart from the fitted boundaries.

``--jobs N`` traces in N local worker processes (at most one per CPU; more is capped with a warning);
``--scheduler`` uses dask instead. Ctrl-C (SIGINT, to the process or its whole group) or SIGTERM stops
at once: nothing new starts, the workers are killed with the files in flight (their partial files
removed), what finished is kept in the manifest, and the exit code is 130 (SIGINT) or 143 (SIGTERM).
Workers also die when this process is killed outright. Exit codes: 0 all traced (or skipped), 1 some
file failed, 2 usage errors (bad option, output = input, manifest = output, an output or manifest that is a
pipe or a device (``-o /dev/null``; ``-o -`` is stdout), empty output or a file name for several inputs,
unwritable output directory, unreachable scheduler). ``--fit-param`` and ``--corner-param`` are the library's
``fit_params`` and ``corner_params``; a bad one is named as its option (``--fit-param merge_tolerance must be >= 0``),
not as the library's key (``fit_params['merge_tolerance']``).
"""
from __future__ import annotations

import argparse
import contextlib
import os
import signal
import sys
import threading

__all__ = ["main", "build_parser"]

PROG = "splinecraft"
#: Decimal places of SVG coordinates without ``--decimals`` (``trace_many``'s default).
DEFAULT_DECIMALS = 4


# ---------------------------------------------------------------------------------------------------
# argument parsing
# ---------------------------------------------------------------------------------------------------
def _finite_number(text, low=0.0, inclusive=False):
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
    if not (value >= low if inclusive else value > low) or value == float("inf"):  # NaN fails both
        raise argparse.ArgumentTypeError(f"must be a finite number {'>=' if inclusive else '>'} {low:g}, got {text}")
    return value


def _positive_float(text):
    return _finite_number(text)


def _non_negative_int(text):
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not an integer: {text!r}") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be >= 0, got {text}")
    return value


def _decimals(text):
    from .spline.svg import MAX_DECIMALS

    value = _non_negative_int(text)
    if value > MAX_DECIMALS:
        raise argparse.ArgumentTypeError(f"must be <= {MAX_DECIMALS}, got {text}")
    return value


def _positive_int(text):
    value = _non_negative_int(text)
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be >= 1, got {text}")
    return value


def _time_budget(text):
    """``--time-budget``: seconds (> 0) or ``none`` (no budget), as the library's ``time_budget=``."""
    return None if text.strip().lower() == "none" else _finite_number(text)


def _noise_factor(text):
    return _finite_number(text, inclusive=True)


def _batch_size(text):
    if text == "auto":
        return text
    return _positive_int(text)


def _threshold(text):
    """``--threshold``: a method name of the library (``background``, ``otsu``, ``sauvola``, ``local``) or a fraction of white."""
    from .capture._binarize import THRESHOLD_METHODS, check_threshold

    if text in THRESHOLD_METHODS:
        return text
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"expected one of {', '.join(THRESHOLD_METHODS)} or a number in [0, 1], got {text!r}") from None
    try:
        return check_threshold(value)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be in [0, 1] (a fraction of white), got {text}") from None


def _connectivity(text):
    """``--connectivity``: ``minority``, 4 or 8, as the library's ``connectivity=``."""
    from .capture.contour import CONNECTIVITIES

    for choice in CONNECTIVITIES:
        if text == str(choice):
            return choice
    raise argparse.ArgumentTypeError(
        f"expected one of {', '.join(map(str, CONNECTIVITIES))}, got {text!r}")


def _trace_defaults():
    """The keyword defaults of :func:`splinecraft.capture.trace.trace` (the CLI's defaults follow them)."""
    import inspect

    from .capture.trace import trace

    return {name: parameter.default for name, parameter in inspect.signature(trace).parameters.items()
            if parameter.default is not inspect.Parameter.empty}


def _scalar(value):
    """One ``--corner-param`` value: an int, a float, true/false, else the text."""
    for convert in (int, float):
        try:
            return convert(value)
        except ValueError:
            pass
    lowered = value.lower()
    if lowered in ("true", "false"):
        return lowered == "true"
    return value


def _key_value(text):
    """``--corner-param NAME=VALUE``; ``VALUE`` with commas is a tuple (tangent-jump's ``flank=4,10``: a pair the
    option could not give before, so the detector's 'must be a pair of integers' could not be met)."""
    key, sep, value = text.partition("=")
    if not sep or not key.isidentifier():
        raise argparse.ArgumentTypeError(f"expected NAME=VALUE, got {text!r}")
    if "," in value:
        return key, tuple(_scalar(part.strip()) for part in value.split(","))
    return key, _scalar(value)


def build_parser() -> argparse.ArgumentParser:
    from . import __version__
    from .capture.contour import CONNECTIVITIES
    from .capture.corners import CORNER_METHODS
    from .capture.fitting import KNOT_METHODS, THESIS_METHODS
    from .capture.image import DEFAULT_THRESHOLD, THRESHOLD_METHODS

    defaults = _trace_defaults()

    parser = argparse.ArgumentParser(
        prog=PROG,
        description="Design and capture planar shapes with smooth generic cubic splines.",
    )
    parser.add_argument("--version", action="version", version=f"{PROG} {__version__}")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND")
    commands.required = True

    tracer = commands.add_parser(
        "trace",
        help="trace bitmaps into smooth outlines (SVG or JSON)",
        description="Trace the outline of each bitmap (outer contours and holes) into closed cubic splines: "
                    "chain-code boundary, corners, spline fit with knot insertion until the error is "
                    "below EPSILON pixels. The compiled kernels (numba) are cached on disk; the README's "
                    "set-up compiles them. On an empty cache the first trace of a small bitmap (up to "
                    "24 000 pixel edges) runs them interpreted while a background process compiles them, "
                    "and a larger one waits for the compile (seconds, in parallel); later processes load "
                    "the cache in well under a second (BENCHMARKS.md, 'Session 31: the first call "
                    "interpreted').",
    )
    tracer.add_argument("inputs", nargs="+", metavar="IN",
                        help="image files (PNG, JPEG, BMP, GIF, TIFF) or quoted glob patterns ('scans/**/*.png')")
    tracer.add_argument("-o", "--output", required=True, metavar="OUT",
                        help="output file for one input ('-' = stdout), directory for several")
    tracer.add_argument("--format", choices=("svg", "json"), default=None,
                        help="output format (default: from OUT's suffix, else svg)")
    tracer.add_argument("--epsilon", type=_positive_float, default=defaults["epsilon"],
                        help=f"error threshold of knot insertion in pixels (default {defaults['epsilon']:g})")
    tracer.add_argument("--method", choices=sorted(KNOT_METHODS), default=None,
                        help="knot-insertion algorithm (default: the library default)")
    tracer.add_argument("--corner-method", choices=sorted(CORNER_METHODS), default=None,
                        help="corner detector (default: the library default)")
    tracer.add_argument("--corner-param", type=_key_value, action="append", default=[], metavar="NAME=VALUE",
                        help="corner detector parameter, repeatable (e.g. --corner-param min_turn=30 for the default "
                             "tangent-jump, --corner-method srm05 --corner-param ta=150 for the thesis's); a value "
                             "with commas is a tuple (flank=4,10)")
    tracer.add_argument("--fit-param", type=_key_value, action="append", default=[], metavar="NAME=VALUE",
                        help="option of the spline fit, repeatable (the library's fit_params: --fit-param "
                             "merge_tolerance=0 for the thesis's C2 fit, --fit-param geometric_corners=true; "
                             "docs/capture.md §12)")
    tracer.add_argument("--seed", type=_non_negative_int, default=None,
                        help="seed of the random knot-insertion methods (--method "
                             + ", ".join(THESIS_METHODS) + f"; default {defaults['seed']}); refused with lsq, "
                             "which draws no random numbers")
    tracer.add_argument("--tau", type=float, default=defaults["tau"], help="distance constraint of Algs 4.2/4.3")
    tracer.add_argument("--max-iterations", type=_positive_int, default=defaults["max_iterations"],
                        help="bound on knot-insertion iterations per boundary "
                             f"(default {defaults['max_iterations']})")
    threshold_default = defaults["threshold"] or DEFAULT_THRESHOLD
    tracer.add_argument("--threshold", type=_threshold, default=defaults["threshold"],
                        metavar="{" + ",".join(THRESHOLD_METHODS) + "}|NUMBER",
                        help="gray threshold: a method (background: half way between paper and ink under the local "
                             "lighting; otsu: one global level; sauvola, local: a level per pixel from a window) or a fraction of white in [0, 1] "
                             f"(default {threshold_default})")
    tracer.add_argument("--invert", action="store_true", default=defaults["invert"],
                        help="light pixels are the shape")
    tracer.add_argument("--min-speck-area", type=_non_negative_int, default=defaults["min_speck_area"],
                        help="remove specks and holes with fewer pixels (0: keep all; default: "
                             + ("from the image's noise estimate" if defaults["min_speck_area"] is None
                                else str(defaults["min_speck_area"])) + ")")
    tracer.add_argument("--connectivity", type=_connectivity, default=defaults["connectivity"],
                        metavar="{" + ",".join(map(str, CONNECTIVITIES)) + "}",
                        help="ink connectivity (minority: decided at each diagonal contact, the locally rarer "
                             f"colour is joined; default {defaults['connectivity']})")
    tracer.add_argument("--contour", choices=("outline", "pixels"), default=defaults["contour"],
                        help=f"fit the crack outline or the pixel-centre chain (default {defaults['contour']})")
    tracer.add_argument("--noise-factor", type=_noise_factor, default=defaults["noise_factor"],
                        help="on ragged (scanned) boundaries the fit's tolerance is this times the boundary noise "
                             f"estimate (0: always EPSILON; default {defaults['noise_factor']:g})")
    tracer.add_argument("--time-budget", type=_time_budget, default=defaults["time_budget"], metavar="SECONDS|none",
                        help="seconds for corner detection and fitting per file; boundaries not started in time "
                             "get the polygon of their contour, and a note says so (a page of text needs more "
                             f"than the default: none = no budget; default {defaults['time_budget']:g})")
    tracer.add_argument("--max-pixels", type=_positive_int, default=defaults["max_pixels"], metavar="N",
                        help="refuse images of more than N pixels, read from the file's header before decoding "
                             f"(a decompression bomb costs nothing; default {defaults['max_pixels']})")
    tracer.add_argument("--decimals", type=_decimals, default=None,
                        help=f"decimal places of SVG coordinates (default {DEFAULT_DECIMALS}; not with JSON output, "
                             "which keeps full precision)")
    tracer.add_argument("-j", "--jobs", type=_non_negative_int, default=None,
                        help="files traced in parallel by local worker processes (0 = one per CPU; default 1; "
                             "capped at the CPU count); with --scheduler: its number of workers")
    tracer.add_argument("--scheduler", default=None, metavar="threads|processes|synchronous|ADDRESS",
                        help="trace with dask: one of its local schedulers, or the address of a dask scheduler "
                             "(tcp://host:8786); needs pip install 'splinecraft[dask]'")
    tracer.add_argument("--resume", action=argparse.BooleanOptionalAction, default=True,
                        help="skip files that the manifest shows finished with the same input, settings and "
                             "output (default: --resume)")
    tracer.add_argument("--manifest", default=None, metavar="PATH",
                        help="manifest file (default: OUT/splinecraft-manifest.jsonl when OUT is a directory)")
    tracer.add_argument("--batch-size", type=_batch_size, default="auto", metavar="N|auto",
                        help="files per task for parallel runs (default auto: tasks of about 0.1 s)")
    tracer.add_argument("-q", "--quiet", action="store_true", help="no progress bar or summary")
    tracer.add_argument("-v", "--verbose", action="store_true", help="print the stats of each file on stderr")
    tracer.set_defaults(command_parser=tracer)
    return parser


def _stdout_conflicts(args) -> str | None:
    """Why the options of ``args`` cannot go together, or ``None``: ``-o -`` traces its one input in this process
    and writes no file, so the options of file outputs (``--manifest``, ``--jobs``, ``--scheduler``, a
    ``--batch-size`` other than ``auto``) would be ignored; they are refused instead."""
    if args.output != "-":
        return None
    given = [option for option, value in (("--manifest", args.manifest), ("--jobs", args.jobs),
                                          ("--scheduler", args.scheduler))
             if value is not None]
    if args.batch_size != "auto":
        given.append("--batch-size")
    if not given:
        return None
    return (f"-o - (stdout) does not take {', '.join(given)}: it traces its one input in this process and writes "
            "no file (no manifest, nothing to run in parallel); give an output file or directory to use "
            f"{'it' if len(given) == 1 else 'them'}")


def _unused_options(args) -> str | None:
    """Why an option of ``args`` would have no effect, or ``None``: ``--seed`` with a knot-insertion method that draws
    no random numbers (``lsq``, the default) is refused, as the library refuses ``tau`` and ``fuzzy_weights`` for the
    methods that do not use them (:func:`splinecraft.capture.fitting.options.check_tau`, ``check_options``)."""
    from .capture.fitting import DEFAULT_METHOD, THESIS_METHODS

    method = args.method or DEFAULT_METHOD
    if args.seed is not None and method not in THESIS_METHODS:
        which = f"--method {method}" if args.method else f"the default --method {method}"
        return (f"--seed is used by the random knot-insertion methods ({', '.join(THESIS_METHODS)}) only, not "
                f"{which}, which draws no random numbers: leave --seed out, or give one of those methods")
    return None


# ---------------------------------------------------------------------------------------------------
# work
# ---------------------------------------------------------------------------------------------------
class Interrupted(KeyboardInterrupt):
    """SIGINT or SIGTERM arrived: the run stops (exit code 128 + signal number)."""

    def __init__(self, signum):
        super().__init__(signal.Signals(signum).name)
        self.signum = signum


@contextlib.contextmanager
def _signals_raise():
    """SIGINT and SIGTERM raise :class:`Interrupted` in the main thread; further ones are ignored while the
    run cleans up (workers killed, partial files removed, manifest written), then the old handlers return.

    Yields :func:`check`, which raises :class:`Interrupted` again if a signal has arrived: Python runs a signal
    handler between any two bytecodes of the main thread, also inside a ``__del__`` or a weakref callback
    (a zip file's clean-up, say), where the exception it raises is printed and dropped. The run calls
    ``check`` after every finished file and once at its end, so such a signal still stops it."""
    received = []

    def check():
        if received:
            raise Interrupted(received[0])

    if threading.current_thread() is not threading.main_thread():
        yield check
        return
    stopping = (signal.SIGINT, signal.SIGTERM)

    def handler(signum, frame):
        for number in stopping:
            signal.signal(number, signal.SIG_IGN)
        received.append(signum)
        raise Interrupted(signum)

    previous = {number: signal.signal(number, handler) for number in stopping}
    try:
        yield check
    finally:
        for number, old in previous.items():
            signal.signal(number, old)


#: Suffixes of an output file: ``-o NAME.svg`` with several inputs is a mistake, not a directory name.
OUTPUT_SUFFIXES = (".svg", ".json")
#: Suffixes of image files: an output so named would hold SVG or JSON text (and ``-o other.png`` would overwrite
#: another image with it), refused.
IMAGE_SUFFIXES = (".png", ".jpg", ".jpeg", ".gif", ".bmp", ".tif", ".tiff", ".webp", ".pbm", ".pgm", ".ppm", ".pnm",
                  ".mpo", ".psd", ".ico")


def _is_an_input(output, inputs) -> bool:
    """Whether the file ``output`` is one of ``inputs`` (``run_batch`` refuses it then, saying so)."""
    if not os.path.exists(output):
        return False
    return any(os.path.exists(source) and os.path.samefile(output, source) for source in inputs)


def _plan_outputs(inputs, output, fmt):
    """Pair every input with its output path; returns (pairs, format) or raises ValueError.

    Refused before anything is traced: an empty ``output``, ``-`` with several inputs, an output named
    like a file (:data:`OUTPUT_SUFFIXES`) for several inputs unless it is an existing directory or ends
    with a separator (it would become a directory called ``out.svg``), one output file named like an image
    (:data:`IMAGE_SUFFIXES`) or like the other format than ``--format`` asks for."""
    from ._validation import blank_text

    if blank_text(output):
        raise ValueError(f"-o/--output is {blank_text(output)}: give an output file, a directory, or - for stdout")
    is_directory = os.path.isdir(output) or output.endswith(("/", os.sep))
    single = len(inputs) == 1 and not is_directory
    if output == "-":
        if len(inputs) != 1:
            raise ValueError("-o - (stdout) takes exactly one input")
        return [(inputs[0], "-")], fmt or "svg"
    if single:
        suffix = os.path.splitext(output)[1].lower()
        if suffix in IMAGE_SUFFIXES and not _is_an_input(output, inputs):  # that one: "also an input", below
            raise ValueError(f"-o {output} names an image file, but the output is {(fmt or 'svg').upper()} text: name "
                             f"it {os.path.splitext(output)[0]}.{fmt or 'svg'}")
        if fmt is not None and suffix in OUTPUT_SUFFIXES and suffix != f".{fmt}":
            raise ValueError(f"-o {output} names {'an' if suffix == '.svg' else 'a'} {suffix[1:].upper()} file, but "
                             f"--format {fmt} asks for "
                             f"{fmt.upper()}: leave --format out, or name the output {os.path.splitext(output)[0]}.{fmt}")
        if fmt is None:
            fmt = "json" if suffix == ".json" else "svg"
        return [(inputs[0], output)], fmt
    fmt = fmt or "svg"
    if not is_directory and output.lower().endswith(OUTPUT_SUFFIXES):
        raise ValueError(f"-o {output} names a file, but {len(inputs)} inputs need an output directory "
                         f"(give a directory, or {output}{os.sep} to create one with that name)")
    if os.path.exists(output) and not os.path.isdir(output):
        raise ValueError(f"{output} exists and is not a directory (several inputs need an output directory)")
    pairs, seen = [], {}
    for source in inputs:
        name = os.path.splitext(os.path.basename(source))[0] + "." + fmt
        if name in seen:
            raise ValueError(f"{seen[name]} and {source} would both be written to {name}")
        seen[name] = source
        pairs.append((source, os.path.join(output, name)))
    return pairs, fmt


def _job_count(jobs, scheduler):
    """``--jobs``: 0 = one per CPU; more than the CPUs is capped, with a warning line."""
    from .batch import cpu_count

    if jobs is None:
        return None if scheduler is not None else 1
    cpus = cpu_count()
    if jobs == 0:
        return cpus
    if jobs > cpus:
        print(f"{PROG}: warning: --jobs {jobs} is more than the {cpus} CPUs of this machine; using {cpus}",
              file=sys.stderr)
        return cpus
    return jobs


#: The library's argument spellings in messages -> this command's options (``run_batch``'s ``spelling``,
#: applied in order to each file's warning and error lines): the time budget note's advice, the unconverged
#: boundaries' ``max_iterations=N reached``, the polarity warning's ``invert=True``, speck removal's
#: ``min_speck_area``, the "no shape found" advice's ``threshold='alpha'``, the size cap's ``max_pixels``.
OPTION_SPELLING = (
    ("trace(time_budget=None)", "--time-budget none"),
    ("max_iterations=", "--max-iterations "),
    ("invert=True", "--invert"),
    ("min_speck_area=", "--min-speck-area "),
    ("min_speck_area", "--min-speck-area"),
    ("threshold='alpha'", "--threshold alpha"),
    ("max_pixels=", "--max-pixels "),
    ("max_pixels", "--max-pixels"),
    ("see threshold/invert", "see --threshold/--invert"),
)


#: The library's names of the command's mapping options in messages -> their options (:func:`_spelled`):
#: ``fit_params['merge_tolerance'] must be >= 0`` is ``--fit-param merge_tolerance must be >= 0`` here.
MAPPING_OPTIONS = (("fit_params", "--fit-param"), ("corner_params", "--corner-param"))


def _spelled(message) -> str:
    """A message of the library about a bad option as this command spells the option (:data:`MAPPING_OPTIONS`):
    ``fit_params['NAME']`` -> ``--fit-param NAME``, ``fit_params has an unknown key`` -> ``--fit-param has an
    unknown name``; a message that begins with ``tau`` begins with ``--tau``."""
    import re

    text = str(message)
    text = re.sub(r"^tau\b", "--tau", text)  # tau is the one scalar option passed to the library unchecked
    for name, option in MAPPING_OPTIONS:
        text = re.sub(rf"\b{name}\['([A-Za-z_][A-Za-z0-9_]*)'\]", rf"{option} \1", text)
        text = re.sub(rf"\b{name} (has an unknown|has an unexpected) (?:keyword|key)\b", rf"{option} \1 name", text)
    return text


def _summary_line(stats, seconds):
    """The ``-v`` line of one file. Boundaries a spent time budget left as polygons are counted apart: their
    deviation (0, they are their contour) and "convergence" are not those of a fit, so the iterations, the
    deviation and convergence are said of the fitted boundaries only, and not at all when none was fitted."""
    head = (f"{stats['boundaries']} boundaries ({stats['holes']} holes), {stats['contour_points']} contour points, "
            f"{stats['corners']} corners, {stats['knots_inserted']} knots inserted, {stats['segments']} segments")
    fit = (f"{stats['iterations']} iterations, max deviation {stats['hausdorff']:.3g} px, "
           f"{'converged' if stats['converged'] else 'not converged'}")
    polygons = stats.get("polygons") or 0  # absent from the manifests of earlier versions
    if not polygons:
        return f"{head}, {fit}, {seconds * 1e3:.0f} ms"
    fitted = stats["boundaries"] - polygons
    return (f"{head}, {fitted} fitted{f' ({fit})' if fitted else ''}, {polygons} kept as polygons "
            f"(time budget), {seconds * 1e3:.0f} ms")


#: How the warning lines of a spent time budget begin (``batch._work.note_lines``): the command says it in lines
#: of its own (:func:`_budget_warnings`), not with ``-q``.
BUDGET_CATEGORY = "TimeBudget: "


def _budget_warnings(source, stats, time_budget):
    """The lines saying that the time budget left boundaries of ``source`` as polygons, or stopped the knot
    rounds of some (the record's ``budget_stopped``)."""
    stats = stats or {}
    polygons, stopped = stats.get("polygons") or 0, stats.get("budget_stopped") or 0  # absent from earlier manifests
    lines = []
    if polygons:
        lines.append(f"{PROG}: {source}: time budget {time_budget:g} s reached: {polygons} of {stats['boundaries']} "
                     "boundaries kept as polygons (use --time-budget none or a larger value)")
    if stopped:
        lines.append(f"{PROG}: {source}: time budget {time_budget:g} s reached: the knot rounds of {stopped} of "
                     f"{stats['boundaries']} boundaries stopped before convergence (use --time-budget none or a "
                     "larger value)")
    return lines


def _file_messages(record, quiet, time_budget):
    """The stderr lines of one traced file: every warning of its record (also with ``-q``: they say the output may
    not be what was meant), but those of a spent time budget, which :func:`_budget_warnings` words (not with
    ``-q``); then its error, if it failed."""
    lines = [f"{PROG}: {record.input}: warning: {line}" for line in record.warnings
             if not line.startswith(BUDGET_CATEGORY)]
    if record.status == "failed":
        lines.append(f"{PROG}: {record.input}: {record.error}")
    elif record.status == "ok" and not quiet:
        lines += _budget_warnings(record.input, record.stats, time_budget)
    return lines


def _trace_to_stdout(source, fmt, options, decimals, quiet=False, verbose=False) -> int:
    from .batch import render, run_batch
    from .batch._plan import PlannedFile

    planned = PlannedFile(index=0, source=source, label=source, output=None, title=os.path.basename(source))
    (record,) = run_batch([planned], trace_params=options, progress=False, format=fmt, decimals=decimals,
                          spelling=OPTION_SPELLING)
    for line in _file_messages(record, quiet, options["time_budget"]):
        print(line, file=sys.stderr)
    if record.status != "ok":
        return 1
    if verbose:
        print(f"{record.input}: {_summary_line(record.stats, record.time_s)}", file=sys.stderr)
    sys.stdout.buffer.write(render(record.result, fmt, decimals, planned.title))
    sys.stdout.flush()
    return 0


def _expand_patterns(inputs) -> list:
    """The inputs with every quoted glob pattern (``'scans/*.png'``, ``'**/*.png'``: a pattern that is no existing
    file) expanded as ``trace_many`` expands it (sorted matching files, ``**`` recursive), so that a folder of
    more files than a shell can pass works too; ``ValueError`` naming a pattern that matches no file."""
    from .batch._plan import expand_inputs

    expanded = []
    for text in inputs:
        try:
            expanded.extend(expand_inputs([text]))
        except ValueError:
            raise ValueError(f"the pattern {text!r} matches no file") from None
    return expanded


def _run_trace(args) -> int:
    from .batch import MANIFEST_NAME, run_batch
    from .batch._plan import PlannedFile

    try:
        pairs, fmt = _plan_outputs(_expand_patterns(args.inputs), args.output, args.format)
    except ValueError as exc:
        print(f"{PROG}: error: {exc}", file=sys.stderr)
        return 2
    if args.decimals is not None and fmt == "json":
        print(f"{PROG}: error: --decimals applies to SVG output only; JSON output (--format json, OUT.json) keeps "
              "full precision: leave --decimals out, or write SVG", file=sys.stderr)
        return 2
    decimals = DEFAULT_DECIMALS if args.decimals is None else args.decimals
    options = {
        "epsilon": args.epsilon, "method": args.method, "corner_method": args.corner_method,
        "corner_params": dict(args.corner_param) or None,
        "fit_params": dict(args.fit_param) or None,
        "seed": _trace_defaults()["seed"] if args.seed is None else args.seed, "tau": args.tau,
        "max_iterations": args.max_iterations, "threshold": args.threshold, "invert": args.invert,
        "min_speck_area": args.min_speck_area, "connectivity": args.connectivity, "contour": args.contour,
        "noise_factor": args.noise_factor, "time_budget": args.time_budget, "max_pixels": args.max_pixels,
    }
    if pairs[0][1] == "-":
        try:
            return _trace_to_stdout(pairs[0][0], fmt, options, decimals, quiet=args.quiet, verbose=args.verbose)
        except (ValueError, TypeError, ImportError) as exc:  # a bad option: one line, as with a file output
            print(f"{PROG}: error: {_spelled(exc)}", file=sys.stderr)
            return 2
    plan = [PlannedFile(index=k, source=source, label=source, output=os.path.abspath(destination),
                        title=os.path.basename(source)) for k, (source, destination) in enumerate(pairs)]
    manifest = args.manifest
    if manifest is None and (len(pairs) > 1 or os.path.isdir(args.output) or args.output.endswith(("/", os.sep))):
        manifest = os.path.join(args.output, MANIFEST_NAME)
    counts = {"ok": 0, "failed": 0, "skipped": 0}

    stop_if_signalled = None

    def report(record):
        from tqdm import tqdm

        stop_if_signalled()
        counts[record.status] = counts.get(record.status, 0) + 1
        for line in _file_messages(record, args.quiet, args.time_budget):
            tqdm.write(line, file=sys.stderr)
        if record.status == "ok" and args.verbose:
            tqdm.write(f"{record.input}: {_summary_line(record.stats, record.time_s)}", file=sys.stderr)

    show = len(pairs) > 1 and not args.quiet and sys.stderr.isatty()
    try:
        with _signals_raise() as stop_if_signalled:
            result = run_batch(plan, manifest=manifest, scheduler=args.scheduler,
                               jobs=_job_count(args.jobs, args.scheduler), batch_size=args.batch_size,
                               resume=args.resume, format=fmt, decimals=decimals, progress=show,
                               on_record=report, trace_params=options, spelling=OPTION_SPELLING)
            stop_if_signalled()
    except Interrupted as stop:
        finished = counts["ok"] + counts["skipped"]
        print(f"{PROG}: interrupted by {signal.Signals(stop.signum).name}: {finished} of {len(pairs)} files "
              "finished and kept; run the same command again to resume", file=sys.stderr)
        return 128 + stop.signum
    except KeyboardInterrupt:
        print(f"{PROG}: interrupted", file=sys.stderr)
        return 130
    except (ValueError, TypeError, OSError, ImportError) as exc:
        print(f"{PROG}: error: {_spelled(exc)}", file=sys.stderr)
        return 2
    failures = counts["failed"]
    if result.manifest_error:
        print(f"{PROG}: {result.manifest_error} (a later run cannot skip these files)", file=sys.stderr)
    if not args.quiet and counts["skipped"]:
        print(f"{PROG}: {counts['skipped']} of {len(pairs)} files already traced (manifest), skipped",
              file=sys.stderr)
    if failures and len(pairs) > 1 and not args.quiet:
        print(f"{PROG}: {failures} of {len(pairs)} files failed", file=sys.stderr)
    return 1 if failures or result.manifest_error else 0


def main(argv=None) -> int:
    """Entry point of the ``splinecraft`` console script; returns the exit code."""
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command == "trace":
        conflict = _stdout_conflicts(args) or _unused_options(args)
        if conflict:
            args.command_parser.error(conflict)  # a usage error: exit code 2
        return _run_trace(args)
    parser.error(f"unknown command {args.command!r}")  # pragma: no cover - argparse checks choices
    return 2


if __name__ == "__main__":
    sys.exit(main())
