"""Running a study's samples (deployfx.study): the task a worker runs for one sample, and the
Dask loop that submits one task per pending sample and stores each result as it arrives.

The task is sent to the workers once (``Client.scatter(..., broadcast=True)``); each sample's
task then carries only its parameter values. A sample's exception is caught on the worker and
returned as a failed record (its error recorded, the study goes on); an exception of the task
itself (a worker that died) is recorded the same way.
"""
from __future__ import annotations

import contextlib
import dataclasses
import inspect
import logging
import os
import sys
import uuid
from dataclasses import dataclass
from typing import Any, Callable, Iterator, Mapping, Optional, Sequence

import numpy as np

from . import _study_outputs, _study_params
from ._study_store import DONE, FAILED


@dataclass(frozen=True)
class _Rebuilt:
    """A dataclass instance in a picklable form (deployfx's contact laws hold C++ objects that do
    not pickle): its class and its init fields, rebuilt on the worker."""

    cls: type
    fields: dict


def portable(value: Any) -> Any:
    """``value`` with every dataclass instance inside (tuples, lists, dicts) made picklable."""
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return _Rebuilt(type(value), {f.name: portable(getattr(value, f.name))
                                      for f in dataclasses.fields(value) if f.init})
    if isinstance(value, (list, tuple)):
        return type(value)(portable(v) for v in value)
    if isinstance(value, dict):
        return {k: portable(v) for k, v in value.items()}
    return value


def rebuilt(value: Any) -> Any:
    """The inverse of :func:`portable`."""
    if isinstance(value, _Rebuilt):
        return value.cls(**{k: rebuilt(v) for k, v in value.fields.items()})
    if isinstance(value, (list, tuple)):
        return type(value)(rebuilt(v) for v in value)
    if isinstance(value, dict):
        return {k: rebuilt(v) for k, v in value.items()}
    return value


@dataclass(frozen=True)
class Task:
    """Everything a worker needs to run any sample of a study (picklable)."""

    factory: Optional[Callable]          #: a scene factory, or None for a scene dict
    scene: Optional[dict]                #: the scene file's dict (a Scene or scene-file base)
    fixed: dict                          #: as :func:`portable` made it
    t_end: float
    dt: float
    scheme: Any
    tolerance: Optional[float]
    outputs: dict
    series: tuple
    time: np.ndarray

    def build(self, values: Mapping[str, Any]):
        """The object whose ``simulate`` runs this sample: the factory's scene, or the compiled
        model of the scene dict with the sample's values set."""
        if self.factory is not None:
            fixed = rebuilt(self.fixed)
            return self.factory(**_study_params.factory_kwargs(self.factory, fixed, values))
        from .scene_file import scene_from_dict

        d = _study_params.set_paths(self.scene, {**self.fixed, **values})
        return scene_from_dict(d).compile()

    def simulate(self, values: Mapping[str, Any]):
        """This sample's :class:`~deployfx.Result` (exceptions propagate)."""
        scene = self.build(values)
        kw: dict[str, Any] = {}
        if self.scheme is not None:
            kw["scheme"] = self.scheme
        if self.tolerance is not None:
            kw["tolerance"] = self.tolerance
        try:
            params = inspect.signature(scene.simulate).parameters
        except (TypeError, ValueError):
            params = {}
        if "progress" in params:
            kw["progress"] = False  # a worker's stderr is no place for a bar per run
        return scene.simulate(self.t_end, self.dt, **kw)


def run_sample(task: Task, values: Mapping[str, Any]) -> dict:
    """One sample's record: ``status`` (DONE or FAILED), ``error`` ("" or "Type: message"),
    ``outputs`` {name: float}, ``series`` {name: array on task.time}; ``study_error`` is set when
    the study itself is wrong (an output that no result has)."""
    record: dict[str, Any] = {"status": FAILED, "error": "", "outputs": {}, "series": {}}
    try:
        result = task.simulate(values)
        record["outputs"], record["series"] = _study_outputs.evaluate(
            result, task.outputs, task.series, task.time)
        record["status"] = DONE
    except _study_outputs.OutputError as e:
        record["error"] = str(e)
        record["study_error"] = True
    except Exception as e:  # a failing sample is recorded, never stops the study
        record["error"] = f"{type(e).__name__}: {e}"
    return record


@contextlib.contextmanager
def client_for(workers: Optional[int], client, scheduler: Optional[str],
               processes: bool) -> Iterator[Any]:
    """A dask.distributed Client: ``client`` as given, one connected to ``scheduler``, or an
    embedded LocalCluster of ``workers`` (default: the machine's cores) single-threaded worker
    processes (``processes=False``: threads in this process), closed afterwards."""
    from distributed import Client, LocalCluster

    if client is not None:
        yield client
        return
    if scheduler is not None:
        with Client(scheduler) as c:
            yield c
        return
    n = (os.cpu_count() or 1) if workers is None else workers
    if processes:
        kw = dict(n_workers=n, threads_per_worker=1, processes=True)
    else:  # one worker whose threads share this process (and, later, one compiled model)
        kw = dict(n_workers=1, threads_per_worker=n, processes=False)
    with LocalCluster(dashboard_address=None, silence_logs=logging.ERROR, **kw) as cluster, \
            Client(cluster) as c:
        yield c


def execute(client, task: Task, design: Mapping[str, np.ndarray], pending: Sequence[int],
            writer, progress: bool) -> None:
    """Run the ``pending`` samples on ``client``, one task each, storing each record with
    ``writer`` as it arrives. A record flagged ``study_error`` cancels the rest and raises
    ValueError (the sample stays pending). Interrupted (Ctrl-C), it flushes what finished."""
    from distributed import as_completed

    names = list(design)
    token = uuid.uuid4().hex[:8]
    task_f = client.scatter(task, broadcast=True, hash=False)
    values = [{k: design[k][i].item() for k in names} for i in pending]
    keys = [f"deployfx-sample-{i}-{token}" for i in pending]
    submitted = client.map(run_sample, [task_f] * len(keys), values, key=keys, pure=False)
    futures = {f.key: (f, int(i)) for f, i in zip(submitted, pending)}
    del submitted
    bar, failed = None, 0
    if progress:
        from tqdm.auto import tqdm

        bar = tqdm(total=len(pending), unit="sample", desc="study", file=sys.stderr)
    try:
        for batch in as_completed(list(f for f, _ in futures.values())).batches():
            outcomes = client.gather(batch, errors="skip")  # results of the tasks that succeeded
            done = {f.key: r for f, r in zip([f for f in batch if f.status == "finished"], outcomes)}
            for f in batch:
                i = futures.pop(f.key)[1]
                outcome = done.get(f.key)
                if outcome is None:  # the task itself failed: a worker died, say
                    exc = f.exception()
                    outcome = {"status": FAILED, "error": f"{type(exc).__name__}: {exc}",
                               "outputs": {}, "series": {}}
                if outcome.get("study_error"):
                    raise ValueError(f"the study's outputs do not fit its runs (sample {i}): "
                                     f"{outcome['error']}")
                writer.add(i, outcome)
                if outcome["status"] == FAILED:
                    failed += 1
                if bar is not None:
                    bar.update(1)
                    if failed:
                        bar.set_postfix(failed=failed, refresh=False)
    finally:
        writer.flush()
        if futures:
            client.cancel([f for f, _ in futures.values()])
        if bar is not None:
            bar.close()
