"""One executor helper for synthesis restarts, sweeps and batches of simulations.

``mapper(workers, scheduler)`` is a context manager giving an ordered ``map(fn, items)``: the plain
built-in for one worker, a process pool on this machine for ``workers > 1``, or a Dask distributed client
when a scheduler address is given. Results come back in the items' order, so a computation whose items
carry their own seeds gives the same answer for any number of workers.
"""

from __future__ import annotations

import contextlib
import multiprocessing
import re
from concurrent.futures import ProcessPoolExecutor

from analytic import ParameterError

# the one line every --scheduler path gives where Dask is missing (pyproject.toml: the ``dask`` extra)
INSTALL_DASK = "pip install 'linkage[dask]'"


@contextlib.contextmanager
def mapper(workers: int = 1, scheduler: str | None = None):
    """Yield ``map(fn, items) -> iterator`` in the items' order.

    Parameters
    ----------
    workers : processes on this machine (1: run in this process)
    scheduler : a Dask scheduler address (``tcp://host:8786``); ``"local"`` starts a
        ``dask.distributed.LocalCluster`` of ``workers`` processes
    """
    if workers < 1:
        raise ParameterError(f"--workers {workers} must be >= 1")
    if scheduler:
        check_scheduler(scheduler)                 # an address Dask's own parser would raise a ValueError on
        try:
            import dask
            from dask.distributed import Client, LocalCluster
        except ImportError:
            raise ParameterError(f"--scheduler {scheduler} needs Dask, an optional extra: {INSTALL_DASK}") from None
        cluster = scratch = None
        settings = contextlib.ExitStack()
        try:
            if scheduler == "local":     # its scheduler's and workers' scratch space in a folder of its own,
                import tempfile          # removed after (else dask-scratch-space is left in the temp folder)
                scratch = tempfile.TemporaryDirectory(prefix="linkage-dask-")
                settings.enter_context(dask.config.set({"temporary-directory": scratch.name}))
                cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                       dashboard_address=None, local_directory=scratch.name)
                client = Client(cluster)
            else:
                client = Client(scheduler, timeout=10)
        except OSError as exc:
            settings.close()
            if scratch is not None:
                scratch.cleanup()
            raise ParameterError(f"--scheduler {scheduler}: cannot connect ({exc})") from None
        try:
            yield lambda fn, items: iter(client.gather(client.map(fn, list(items), pure=False)))
        finally:
            client.close()
            if cluster is not None:
                cluster.close()
            settings.close()
            if scratch is not None:
                scratch.cleanup()
        return
    if workers == 1:
        yield map
        return
    # not fork: a process that has run the compiled solver holds GNU OpenMP's threads, and a child forked
    # from it is killed ("fork() called from a process already using GNU OpenMP"); a fork server's children
    # start from a clean process that imports what the mapped function needs
    methods = multiprocessing.get_all_start_methods()
    context = multiprocessing.get_context("forkserver" if "forkserver" in methods else "spawn")
    with ProcessPoolExecutor(max_workers=workers, mp_context=context) as pool:
        yield pool.map


_ADDRESS = re.compile(r"(?:(?:tcp|tls)://)?(\[[0-9A-Fa-f:.]+\]|[A-Za-z0-9_.-]+):([0-9]{1,5})")
"""A scheduler address: ``tcp://HOST:PORT``, ``tls://HOST:PORT`` or ``HOST:PORT`` (an IPv6 host in brackets)."""
_INPROC = re.compile(r"inproc://[0-9A-Za-z_.:/-]+/[0-9]+/[0-9]+")
"""An in-process scheduler's address (a ``LocalCluster(processes=False)`` of the same process)."""


def check_scheduler(text: str) -> str:
    """``--scheduler``: ``local``, a TCP or TLS address with a port in 1..65535 (or an in-process cluster's
    ``inproc://`` address, as a script's ``LocalCluster(processes=False)`` gives), else one line saying the form
    (Dask's own parser raises a ValueError on ``junk``, ``tcp://``, ``http://...``)."""
    m = _ADDRESS.fullmatch(text)
    if text != "local" and not (m and 1 <= int(m.group(2)) <= 65535) and not _INPROC.fullmatch(text):
        raise ParameterError(f"--scheduler {text[:80]!r} is not a Dask scheduler address; give tcp://HOST:PORT "
                             f"(e.g. tcp://127.0.0.1:8786, a running dask scheduler) or local (a cluster here)")
    return text
