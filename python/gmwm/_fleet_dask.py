"""A fleet's recordings as tasks on a Dask distributed cluster (Debian's python3-distributed).

Each task is one recording's task text (the library's fleet_task_text: how to read it and the
study's options); a worker runs gmwm._gmwm.fleet_task on it (the library call a local run
makes, without the GIL) and sends back the record's text, which the client caches and
assembles into the same table as a local run. The workers need the gmwm package importable and
the recordings at the same paths (a shared filesystem).

Two faces:
  runner(scheduler)    the runner gmwm.fleet(..., scheduler=...) hands to the study;
  python -m gmwm._fleet_dask ADDRESS
                       the bridge `gmwm fleet --scheduler ADDRESS` starts: every task line
                       ({"k": k, "task": text}) read from standard input first, then one line
                       per finished task on standard output ({"k": k, "record": text}), as
                       they finish; a task that raises on a worker (the worker cannot run
                       gmwm) ends it with one line on standard error and exit 3.
"""
from __future__ import annotations

import json
import sys
from typing import Any, Callable, Iterable

# Seconds to wait for the scheduler to answer before saying it cannot be reached (Dask's own
# default connect timeout is 30 s; a user who typed a wrong address should hear it sooner).
CONNECT_TIMEOUT_S = 10


def _client(scheduler: Any) -> tuple[Any, bool]:
    """(a distributed.Client for `scheduler`, whether this module made it): an address, or a
    Client or LocalCluster the caller already has."""
    try:
        import distributed
    except ImportError as e:  # pragma: no cover - the message is the test
        raise ImportError("gmwm fleet on a Dask cluster needs python3-distributed (Debian) or the "
                          "'distributed' package") from e
    if isinstance(scheduler, distributed.Client):
        return scheduler, False
    if isinstance(scheduler, distributed.deploy.Cluster):
        return distributed.Client(scheduler), True
    return distributed.Client(str(scheduler), timeout=CONNECT_TIMEOUT_S), True


def _run_task(text: str) -> str:
    """What a worker runs: the record's text of one task text."""
    from gmwm import _gmwm  # imported on the worker

    return _gmwm.fleet_task(text)


class WorkerError(RuntimeError):
    """A task raised on a worker: the worker cannot run gmwm (not installed there, another
    version), since a recording's own faults are its record, never an exception."""


def run_tasks(client: Any, tasks: Iterable[tuple[int, str]], done: Callable[[int, str], None]) -> None:
    """Submits every (k, text) and hands each record back as it finishes: done(k, record).
    A task that raises ends the run with WorkerError (the rest cancelled); a lost cluster
    raises too. What was handed back by then stays handed back (the client has cached it)."""
    import distributed

    futures = {}
    for k, text in tasks:
        # pure=False: two recordings with the same text (the same file listed twice) are two tasks.
        futures[client.submit(_run_task, text, pure=False)] = k
    try:
        for future in distributed.as_completed(list(futures)):
            k = futures.pop(future)
            if future.status != "finished":
                exc = future.exception()
                raise WorkerError(f"a worker could not run recording {k + 1}'s task: {type(exc).__name__}: {exc} "
                                  "(every worker needs the gmwm Python module of this version and the recordings "
                                  "at the same paths)".replace("\n", " "))
            done(k, future.result())
    finally:
        client.cancel(list(futures))


def runner(scheduler: Any) -> Callable[[list[tuple[int, str]], Callable[[int, str], None]], None]:
    """The runner gmwm.fleet hands to the study: runs the tasks on `scheduler` (an address, a
    distributed.Client or a LocalCluster)."""

    def run(items: list[tuple[int, str]], done: Callable[[int, str], None]) -> None:
        client, own = _client(scheduler)
        try:
            run_tasks(client, ((k, text) for k, (_index, text) in enumerate(items)), done)
        finally:
            if own:
                client.close()

    return run


def main(argv: list[str]) -> int:
    """The bridge of `gmwm fleet --scheduler ADDRESS` (the module's docstring)."""
    if len(argv) != 1:
        print("gmwm fleet --scheduler: usage: python -m gmwm._fleet_dask ADDRESS", file=sys.stderr)
        return 2
    tasks = []
    for line in sys.stdin:
        if line.strip():
            item = json.loads(line)
            tasks.append((int(item["k"]), str(item["task"])))

    def emit(obj: dict[str, Any]) -> None:
        sys.stdout.write(json.dumps(obj) + "\n")
        sys.stdout.flush()

    try:
        client, _ = _client(argv[0])
    except Exception as e:  # noqa: BLE001 - any failure to connect is said in one line
        print(f"gmwm fleet --scheduler {argv[0]}: cannot reach the Dask scheduler: {type(e).__name__}: "
              f"{e}".replace("\n", " "), file=sys.stderr)
        return 3
    try:
        run_tasks(client, tasks, lambda k, r: emit({"k": k, "record": r}))
    except WorkerError as e:
        print(f"gmwm fleet --scheduler {argv[0]}: {e}", file=sys.stderr)
        return 3
    except Exception as e:  # noqa: BLE001 - the cluster went away mid-run
        print(f"gmwm fleet --scheduler {argv[0]}: the cluster stopped: {type(e).__name__}: "
              f"{e}".replace("\n", " "), file=sys.stderr)
        return 3
    finally:
        client.close()
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
