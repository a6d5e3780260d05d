"""Command line: ``splinecraft trace IN [IN ...] -o OUT`` (outline capture to SVG or JSON).

Examples
--------
::

    splinecraft trace glyph.png -o glyph.svg
    splinecraft trace scans/*.png -o traced/ --epsilon 1 --method fuzzy --jobs 4
    splinecraft trace logo.png -o - --format json          # JSON to stdout
    splinecraft --version

``OUT`` is a file for one input (``-`` = stdout) and a directory for several (created if needed; each
input ``NAME.ext`` becomes ``OUT/NAME.svg`` or ``.json``). The format follows ``--format``, else the
suffix of a single output file, else SVG. Over several files a progress bar is drawn on stderr when it
is a terminal (never with ``--quiet``). A file that fails gets one line ``splinecraft: FILE: reason``
on stderr while the others still finish; the exit code is then 1 (0 when all succeed, 2 for usage
errors, 130 when interrupted). ``--jobs N`` traces N files in parallel processes.
"""
from __future__ import annotations

import argparse
import os
import shutil
import sys
import time
from concurrent.futures import ProcessPoolExecutor, as_completed

__all__ = ["main", "build_parser"]

PROG = "splinecraft"


# ---------------------------------------------------------------------------------------------------
# argument parsing
# ---------------------------------------------------------------------------------------------------
def _positive_float(text):
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
    if not value > 0 or value == float("inf"):
        raise argparse.ArgumentTypeError(f"must be a finite number > 0, got {text}")
    return value


def _non_negative_int(text):
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not an integer: {text!r}") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be >= 0, got {text}")
    return value


def _positive_int(text):
    value = _non_negative_int(text)
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be >= 1, got {text}")
    return value


def _fraction(text):
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
    if not 0.0 <= value <= 1.0:
        raise argparse.ArgumentTypeError(f"must be in [0, 1] (a fraction of white), got {text}")
    return value


def _key_value(text):
    key, sep, value = text.partition("=")
    if not sep or not key.isidentifier():
        raise argparse.ArgumentTypeError(f"expected NAME=VALUE, got {text!r}")
    for convert in (int, float):
        try:
            return key, convert(value)
        except ValueError:
            pass
    lowered = value.lower()
    if lowered in ("true", "false"):
        return key, lowered == "true"
    return key, value


def build_parser() -> argparse.ArgumentParser:
    from . import __version__
    from .capture.corners import CORNER_METHODS
    from .capture.fitting import DEFAULT_EPSILON, KNOT_METHODS

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
                    "below EPSILON pixels.",
    )
    tracer.add_argument("inputs", nargs="+", metavar="IN", help="image files (PNG, JPEG, BMP, GIF, TIFF)")
    tracer.add_argument("-o", "--output", required=True, metavar="OUT",
                        help="output file for one input ('-' = stdout), directory for several")
    tracer.add_argument("--format", choices=("svg", "json"), default=None,
                        help="output format (default: from OUT's suffix, else svg)")
    tracer.add_argument("--epsilon", type=_positive_float, default=DEFAULT_EPSILON,
                        help=f"error threshold of knot insertion in pixels (default {DEFAULT_EPSILON:g})")
    tracer.add_argument("--method", choices=sorted(KNOT_METHODS), default=None,
                        help="knot-insertion algorithm (default: the library default)")
    tracer.add_argument("--corner-method", choices=sorted(CORNER_METHODS), default=None,
                        help="corner detector (default: the library default)")
    tracer.add_argument("--corner-param", type=_key_value, action="append", default=[], metavar="NAME=VALUE",
                        help="corner detector parameter, repeatable (e.g. --corner-param ta=150)")
    tracer.add_argument("--seed", type=_non_negative_int, default=0, help="seed of the random algorithms")
    tracer.add_argument("--tau", type=float, default=None, help="distance constraint of Algs 4.2/4.3")
    tracer.add_argument("--max-iterations", type=_positive_int, default=200,
                        help="bound on knot-insertion iterations per boundary (default 200)")
    tracer.add_argument("--threshold", type=_fraction, default=None,
                        help="gray threshold as a fraction of white (default: Otsu)")
    tracer.add_argument("--invert", action="store_true", help="light pixels are the shape")
    tracer.add_argument("--min-speck-area", type=_non_negative_int, default=0,
                        help="remove specks and holes with fewer pixels (default 0: keep all)")
    tracer.add_argument("--connectivity", type=int, choices=(4, 8), default=8, help="ink connectivity")
    tracer.add_argument("--contour", choices=("outline", "pixels"), default="outline",
                        help="fit the crack outline (default) or the pixel-centre chain")
    tracer.add_argument("--decimals", type=_non_negative_int, default=4,
                        help="decimal places of SVG coordinates (default 4)")
    tracer.add_argument("-j", "--jobs", type=_non_negative_int, default=1,
                        help="files traced in parallel (0 = one per CPU; default 1)")
    tracer.add_argument("-q", "--quiet", action="store_true", help="no progress bar or summary")
    tracer.add_argument("-v", "--verbose", action="store_true", help="print the stats of each file on stderr")
    return parser


# ---------------------------------------------------------------------------------------------------
# work
# ---------------------------------------------------------------------------------------------------
def _trace_file(source, destination, fmt, options, decimals):
    """Trace one file and write the result; never raises (returns an error line instead)."""
    started = time.perf_counter()
    try:
        from .capture.trace import trace

        result = trace(source, keep_snapshots=False, **options)
        if fmt == "json":
            text = result.to_json()
        else:
            text = result.to_svg(decimals=decimals, title=os.path.basename(source))
        if destination == "-":
            sys.stdout.write(text)
            sys.stdout.flush()
        else:
            temporary = f"{destination}.part{os.getpid()}"
            with open(temporary, "w", encoding="utf-8") as handle:
                handle.write(text)
            os.replace(temporary, destination)
        stats = result.stats
        summary = (
            f"{stats['boundaries']} boundaries ({stats['holes']} holes), {stats['contour_points']} contour points, "
            f"{stats['corners']} corners, {stats['knots_inserted']} knots inserted, {stats['segments']} segments, "
            f"{stats['iterations']} iterations, max deviation {stats['hausdorff']:.3g} px, "
            f"{(time.perf_counter() - started) * 1e3:.0f} ms"
        )
        return source, None, summary
    except Exception as exc:  # noqa: BLE001 - one failed file must not stop the others
        message = str(exc).strip().splitlines()[0] if str(exc).strip() else ""
        if message.startswith(f"{source}: "):  # the loader already names the file
            message = message[len(source) + 2:]
        if isinstance(exc, (ValueError, OSError)) and message:
            reason = message  # expected failures: bad input, unreadable file
        else:
            reason = f"{type(exc).__name__}: {message}" if message else type(exc).__name__
        return source, reason, None


class _Progress:
    """A one-line progress bar on a terminal stream; silent when disabled."""

    def __init__(self, total, stream, enabled):
        self.total, self.stream, self.enabled, self.done = total, stream, enabled, 0
        self.width = shutil.get_terminal_size((80, 20)).columns

    def _draw(self, label=""):
        if not self.enabled:
            return
        counter = f" {self.done}/{self.total} "
        bar_width = max(10, min(40, self.width - len(counter) - 20))
        filled = bar_width * self.done // max(self.total, 1)
        line = f"[{'#' * filled}{'.' * (bar_width - filled)}]{counter}{label}"
        self.stream.write("\r" + line[: self.width - 1].ljust(self.width - 1))
        self.stream.flush()

    def start(self):
        self._draw()

    def advance(self, label):
        self.done += 1
        self._draw(os.path.basename(label))

    def message(self, text):
        if self.enabled:
            self.stream.write("\r" + " " * (self.width - 1) + "\r")
        self.stream.write(text + "\n")
        self.stream.flush()
        self._draw()

    def close(self):
        if self.enabled:
            self.stream.write("\r" + " " * (self.width - 1) + "\r")
            self.stream.flush()


def _plan_outputs(inputs, output, fmt):
    """Pair every input with its output path; returns (pairs, format) or raises ValueError."""
    single = len(inputs) == 1 and not os.path.isdir(output) and not output.endswith(("/", os.sep))
    if output == "-":
        if len(inputs) != 1:
            raise ValueError("-o - (stdout) takes exactly one input")
        return [(inputs[0], "-")], fmt or "svg"
    if single:
        if fmt is None:
            fmt = "json" if output.lower().endswith(".json") else "svg"
        return [(inputs[0], output)], fmt
    fmt = fmt or "svg"
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


def _run_trace(args) -> int:
    try:
        pairs, fmt = _plan_outputs(args.inputs, args.output, args.format)
        if len(pairs) > 1 or (pairs[0][1] != "-" and os.path.dirname(pairs[0][1])):
            directory = args.output if len(pairs) > 1 else os.path.dirname(pairs[0][1])
            os.makedirs(directory, exist_ok=True)
    except (ValueError, OSError) as exc:
        print(f"{PROG}: error: {exc}", file=sys.stderr)
        return 2

    options = {
        "epsilon": args.epsilon, "method": args.method, "corner_method": args.corner_method,
        "corner_params": dict(args.corner_param) or None, "seed": args.seed, "tau": args.tau,
        "max_iterations": args.max_iterations, "threshold": args.threshold, "invert": args.invert,
        "min_speck_area": args.min_speck_area, "connectivity": args.connectivity, "contour": args.contour,
    }
    jobs = args.jobs or os.cpu_count() or 1
    jobs = max(1, min(jobs, len(pairs)))
    progress = _Progress(len(pairs), sys.stderr,
                         enabled=len(pairs) > 1 and not args.quiet and sys.stderr.isatty())
    failures = 0

    def report(source, error, summary):
        nonlocal failures
        if error is not None:
            failures += 1
            progress.message(f"{PROG}: {source}: {error}")
        elif args.verbose:
            progress.message(f"{source}: {summary}")
        progress.advance(source)

    progress.start()
    try:
        if jobs == 1:
            for source, destination in pairs:
                report(*_trace_file(source, destination, fmt, options, args.decimals))
        else:
            from splinecraft import cli as worker_module  # importable name, also under `python -m`

            with ProcessPoolExecutor(max_workers=jobs) as pool:
                futures = {
                    pool.submit(worker_module._trace_file, source, destination, fmt, options, args.decimals): source
                    for source, destination in pairs
                }
                for future in as_completed(futures):
                    try:
                        report(*future.result())
                    except Exception as exc:  # noqa: BLE001 - a crashed worker process
                        report(futures[future], f"worker process failed: {type(exc).__name__}: {exc}", None)
    except KeyboardInterrupt:
        progress.close()
        print(f"{PROG}: interrupted", file=sys.stderr)
        return 130
    progress.close()
    if failures and len(pairs) > 1 and not args.quiet:
        print(f"{PROG}: {failures} of {len(pairs)} files failed", file=sys.stderr)
    return 1 if failures else 0


def main(argv=None) -> int:
    """Entry point of the ``splinecraft`` console script; returns the exit code."""
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command == "trace":
        return _run_trace(args)
    parser.error(f"unknown command {args.command!r}")  # pragma: no cover - argparse checks choices
    return 2


if __name__ == "__main__":
    sys.exit(main())
