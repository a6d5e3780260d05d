"""Where batches run: in the calling process, in local worker processes, on dask's local schedulers, or
on a dask.distributed cluster.

Every runner has the same three calls: ``run(batches, settings, on_done)`` traces the batches and calls
``on_done(records)`` in the calling thread as each batch finishes; ``stop()`` abandons the run at once
(nothing new starts, worker processes are killed, pending tasks cancelled); ``close()`` releases what the
runner started. A batch is ``_work.trace_batch``'s list of items.
"""
from __future__ import annotations

import itertools
import multiprocessing
import os
import re
import sys
import threading
import warnings
from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor, as_completed
from concurrent.futures.process import BrokenProcessPool
from functools import partial

from .._validation import check_int
from ._work import STOP_EVENTS, init_worker_process, trace_batch

LOCAL_SCHEDULERS = ("threads", "processes", "synchronous")
#: Seconds to wait for a dask scheduler at an address before giving up with a clear error.
CONNECT_TIMEOUT_S = 5.0
#: A broken local process pool (a worker died) is restarted this many times in one run.
POOL_RESTARTS = 3
_ADDRESS = re.compile(r"^([a-z][a-z0-9+]*://\S+|[\w.\-]+:\d+)$")
DASK_HINT = "install it with: pip install 'splinecraft[dask]'"


def cpu_count() -> int:
    """CPUs this process may run on (its affinity mask where the system has one)."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):
        return max(1, os.cpu_count() or 1)


def failed_records(batch, reason) -> list:
    return [{"index": item["index"], "status": "failed", "error": reason, "input_sha256": None,
             "output_sha256": None, "stats": None, "result": None, "time_s": 0.0, "warnings": []} for item in batch]


def _import_dask(what):
    try:
        import dask  # noqa: F401
    except ImportError:
        raise ImportError(f"{what} needs dask, which is not installed; {DASK_HINT}") from None
    return dask


def _import_distributed(what):
    try:
        import distributed
    except ImportError:
        raise ImportError(f"{what} needs dask.distributed, which is not installed; {DASK_HINT}") from None
    return distributed


# ---------------------------------------------------------------------------------------------------
# runners
# ---------------------------------------------------------------------------------------------------
class SerialRunner:
    """One file after the other in the calling thread."""

    name = "serial"
    workers = 1

    def run(self, batches, settings, on_done):
        for batch in batches:
            on_done(trace_batch(batch, settings))

    def stop(self):
        pass

    def close(self):
        pass


class _LocalProcesses:
    """A ``ProcessPoolExecutor`` of spawned workers that ignore Ctrl-C and die with this process."""

    def __init__(self, workers):
        self.workers, self.pool = workers, None

    def get(self):
        if self.pool is None:
            self.pool = ProcessPoolExecutor(self.workers, mp_context=multiprocessing.get_context("spawn"),
                                            initializer=init_worker_process, initargs=(os.getpid(),))
        return self.pool

    def kill(self):
        """Kill the workers now (files in flight are abandoned; their temporary files stay for cleanup)."""
        pool, self.pool = self.pool, None
        if pool is None:
            return
        kill_workers = getattr(pool, "kill_workers", None)  # Python >= 3.14
        processes = list((getattr(pool, "_processes", None) or {}).values())
        if kill_workers is not None:
            kill_workers()
        else:  # no public way before Python 3.14
            for process in processes:
                process.kill()
        pool.shutdown(wait=False, cancel_futures=True)
        for process in processes:
            process.join(timeout=2.0)

    def close(self):
        pool, self.pool = self.pool, None
        if pool is not None:
            pool.shutdown(wait=True)


def _run_restarting(processes, batches, on_done, run_once):
    """Run ``batches`` with ``run_once(pending, on_done)``; when a worker process dies (the pool breaks), start
    a new pool and run the unfinished batches again, at most :data:`POOL_RESTARTS` times."""
    pending = dict(enumerate(batches))

    def done(position, records):
        pending.pop(position, None)
        on_done(records)

    for _attempt in range(POOL_RESTARTS + 1):
        try:
            run_once(dict(pending), done)
            return
        except BrokenProcessPool:
            processes.kill()
    for position in list(pending):
        done(position, failed_records(pending[position], (
            f"a worker process died while tracing this file's batch ({POOL_RESTARTS + 1} attempts; a script "
            "that starts worker processes needs the `if __name__ == '__main__':` guard)")))


class PoolRunner:
    """splinecraft's own local worker processes (no dask needed); ``--jobs N`` on the command line."""

    name = "local processes"

    def __init__(self, workers):
        self.workers = workers
        self._processes = _LocalProcesses(workers)

    def run(self, batches, settings, on_done):
        def run_once(pending, done):
            pool = self._processes.get()
            futures = {pool.submit(trace_batch, batch, settings): position for position, batch in pending.items()}
            broken = False
            for future in as_completed(futures):
                position = futures[future]
                try:
                    records = future.result()
                except BrokenProcessPool:
                    broken = True
                    continue
                except Exception as exc:  # noqa: BLE001 - e.g. an input that cannot be pickled
                    records = failed_records(pending[position], f"{type(exc).__name__}: {exc}")
                done(position, records)
            if broken:
                raise BrokenProcessPool("a worker process died")

        _run_restarting(self._processes, batches, on_done, run_once)

    def stop(self):
        self._processes.kill()

    def close(self):
        self._processes.close()


class DaskLocalRunner:
    """dask's local schedulers: ``"threads"``, ``"processes"`` (spawned workers as in :class:`PoolRunner`)
    or ``"synchronous"`` (in the calling thread, for debugging)."""

    def __init__(self, name, workers):
        _import_dask(f"scheduler={name!r}")
        self.name = name
        self.workers = 1 if name == "synchronous" else workers
        self._processes = _LocalProcesses(workers) if name == "processes" else None
        self._threads = None
        self._stop = threading.Event()
        self._run_id = None
        self._tasks = itertools.count()

    def _compute(self, pending, done, settings):
        import dask

        keys = {f"splinecraft-batch-{settings['run']}-{next(self._tasks)}": position for position in pending}
        tasks = [dask.delayed(partial(trace_batch, pending[position], settings), pure=False)(dask_key_name=key)
                 for key, position in keys.items()]

        def posttask(key, records, dsk, state, worker_id):
            if key in keys:
                done(keys[key], records)

        options = {"scheduler": self.name, "callbacks": [(None, None, None, posttask, None)],
                   "optimize_graph": False}
        if self.name == "processes":
            options.update(pool=self._processes.get(), num_workers=self.workers)
        elif self.name == "threads":
            if self._threads is None:
                self._threads = ThreadPoolExecutor(self.workers, thread_name_prefix="splinecraft-trace")
            options.update(pool=self._threads, num_workers=self.workers)
        dask.compute(*tasks, **options)

    def run(self, batches, settings, on_done):
        self._run_id = settings["run"]
        STOP_EVENTS[self._run_id] = self._stop
        if self._processes is not None:
            _run_restarting(self._processes, batches, on_done,
                            lambda pending, done: self._compute(pending, done, settings))
        else:
            self._compute(dict(enumerate(batches)), lambda position, records: on_done(records), settings)

    def stop(self):
        self._stop.set()
        if self._processes is not None:
            self._processes.kill()
        if self._threads is not None:  # threads cannot be killed: they stop after their current file
            threads, self._threads = self._threads, None
            threads.shutdown(wait=True, cancel_futures=True)

    def close(self):
        STOP_EVENTS.pop(self._run_id, None)
        if self._processes is not None:
            self._processes.close()
        if self._threads is not None:
            self._threads.shutdown(wait=True)
            self._threads = None


class DistributedRunner:
    """A dask.distributed cluster: a ``Client``, or a scheduler address to connect to.

    Tasks are submitted in a window of four per worker thread, so the scheduler holds a bounded number of
    tasks however many files there are, and a stopped run starts nothing new. A task whose worker dies is
    run again by the scheduler (dask's ``distributed.scheduler.allowed-failures``).
    """

    name = "distributed"

    def __init__(self, client, owned):
        self.client, self.owned = client, owned
        self._futures = set()
        self._tasks = itertools.count()  # task keys stay unique over the runs of one batch
        nthreads = client.nthreads()
        if not nthreads:
            try:
                client.wait_for_workers(1, timeout=CONNECT_TIMEOUT_S)
            except Exception as exc:  # noqa: BLE001 - distributed raises TimeoutError or its own
                raise ConnectionError(f"scheduler {client.scheduler.address}: no dask worker joined within "
                                      f"{CONNECT_TIMEOUT_S:g} s") from exc
            nthreads = client.nthreads()
        self.workers = max(1, sum(nthreads.values()))

    @classmethod
    def connect(cls, address):
        distributed = _import_distributed(f"scheduler={address!r}")
        try:
            client = distributed.Client(address, timeout=f"{CONNECT_TIMEOUT_S:g}s", set_as_default=False)
        except (OSError, TimeoutError) as exc:
            raise ConnectionError(
                f"scheduler {address!r}: no dask scheduler answered within {CONNECT_TIMEOUT_S:g} s ({exc}); "
                "start one (e.g. `dask scheduler`) or pass a running distributed.Client"
            ) from None
        try:
            return cls(client, owned=True)
        except BaseException:
            client.close()
            raise

    def run(self, batches, settings, on_done):
        from distributed import as_completed as completed

        window = 4 * self.workers
        queue = iter(enumerate(batches))
        positions = {}

        def submit(count, into):
            for _ in range(count):
                position, batch = next(queue, (None, None))
                if batch is None:
                    return
                future = self.client.submit(trace_batch, batch, settings, pure=False,
                                            key=f"splinecraft-batch-{settings['run']}-{next(self._tasks)}")
                positions[future.key] = (position, batch)
                self._futures.add(future)
                into.add(future)

        stream = completed(loop=self.client.loop)
        submit(window, stream)
        for future in stream:
            position, batch = positions.pop(future.key)
            self._futures.discard(future)
            try:
                records = future.result()
            except Exception as exc:  # noqa: BLE001 - e.g. KilledWorker after repeated worker deaths
                records = failed_records(batch, f"{type(exc).__name__}: {exc}")
            future.release()
            on_done(records)
            submit(1, stream)

    def stop(self):
        futures, self._futures = list(self._futures), set()
        if futures:
            try:
                self.client.cancel(futures)
            except Exception:  # noqa: BLE001 - the connection may already be gone
                pass

    def close(self):
        if self.owned:
            self.client.close()


# ---------------------------------------------------------------------------------------------------
# choosing a runner
# ---------------------------------------------------------------------------------------------------
def check_jobs(jobs):
    """``None`` or an int >= 0: 0 is one worker per CPU (as ``--jobs 0``), more than the CPU count is capped
    (with a ``RuntimeWarning``)."""
    if jobs is None:
        return None
    jobs = check_int(jobs, "jobs", minimum=0)
    cpus = cpu_count()
    if jobs == 0:
        return cpus
    if jobs > cpus:
        warnings.warn(f"jobs={jobs} is more than the {cpus} CPUs of this machine; using {cpus}",
                      RuntimeWarning, stacklevel=5)
        jobs = cpus
    return jobs


def _is_client(value) -> bool:
    distributed = sys.modules.get("distributed")  # a Client exists only if distributed was imported
    return distributed is not None and isinstance(value, distributed.Client)


def make_runner(scheduler, jobs, files):
    """The runner for ``scheduler`` (see :func:`splinecraft.batch.trace_many`)."""
    jobs = check_jobs(jobs)
    if scheduler is None:
        workers = min(jobs or 1, files)
        return SerialRunner() if workers <= 1 else PoolRunner(workers)
    if isinstance(scheduler, str) and scheduler in LOCAL_SCHEDULERS:
        return DaskLocalRunner(scheduler, min(jobs or cpu_count(), max(files, 1)))
    if jobs is not None:
        raise ValueError("jobs applies to local schedulers (None, 'threads', 'processes', 'synchronous'); "
                         "a dask cluster has its own workers")
    if isinstance(scheduler, str):
        if not _ADDRESS.match(scheduler):
            raise ValueError(f"scheduler must be None, one of {list(LOCAL_SCHEDULERS)}, a dask scheduler address "
                             f"such as 'tcp://host:8786', or a distributed.Client; got {scheduler!r}")
        return DistributedRunner.connect(scheduler)
    if _is_client(scheduler):
        return DistributedRunner(scheduler, owned=False)
    raise TypeError(f"scheduler must be None, a string or a distributed.Client, got {type(scheduler).__name__}")
