"""What ``chaplygin sweep`` checks before any work: the machine's share of the grid (memory,
disk, time), the worker count, and the scheduler's address (parsed, then asked for the Dask
handshake with a time limit).

Only the address the user names is contacted, and only by :func:`probe_scheduler` and the
Dask client after it: a port that answers HTTP (the dashboard's 8787 instead of 8786), junk
or nothing is refused in one line within the time limit, before the Dask client reads a
length from it (a junk length made it allocate exabytes).
"""

from __future__ import annotations

import ipaddress
import os
import re
import shutil
import socket
import struct
import time
from dataclasses import dataclass
from pathlib import Path

from ..derive.errors import UserInputError

__all__ = [
    "SchedulerAddress",
    "parse_scheduler_address",
    "probe_scheduler",
    "usable_cpus",
    "available_memory",
    "check_workers",
    "GridCost",
    "check_grid_cost",
    "WORKER_BYTES",
    "CHUNK_OVERHEAD_BYTES",
    "CONNECT_TIMEOUT_S",
    "MAX_SWEEP_DAYS",
]

#: Seconds to connect to a scheduler and to receive its handshake (``--connect-timeout``).
CONNECT_TIMEOUT_S = 10.0

#: Memory a worker process needs (measured: 171 MB resident after a small sweep; doubled).
WORKER_BYTES = 400 * 2**20

#: Client and scheduler memory per task (chunk): measured 5.2 kB per submitted task in the
#: process of a LocalCluster's client and scheduler; three times that for the futures, the
#: points of the chunk and its result while it waits to be written.
CHUNK_OVERHEAD_BYTES = 16 * 2**10

#: A sweep whose least time (every point at least as dear as resolving the first one) is
#: longer than this is refused: no run of this machine lasts that long unattended.
MAX_SWEEP_DAYS = 365

#: Longest handshake a Dask scheduler sends (it is about 60 bytes).
_MAX_HANDSHAKE = 64 * 2**10


# ------------------------------------------------------------------------------- scheduler
@dataclass(frozen=True)
class SchedulerAddress:
    """A parsed ``--scheduler``: ``host``, ``port`` and the address given to Dask."""

    host: str
    port: int
    url: str


def parse_scheduler_address(text: str) -> SchedulerAddress:
    """Read ``tcp://HOST:PORT`` (or ``HOST:PORT``; IPv6 in brackets: ``tcp://[::1]:8786``).

    Parameters
    ----------
    text : str
        The ``--scheduler`` value.

    Returns
    -------
    SchedulerAddress

    Raises
    ------
    UserInputError
        Another scheme (``http://``, ``tls://``: this command has no TLS settings), no port,
        a port outside 1..65535, a malformed host.
    """

    def refuse(reason: str) -> UserInputError:
        return UserInputError(f"--scheduler {text!r}: {reason}")

    value = text.strip()
    if not value:
        raise refuse("give the scheduler's address, e.g. tcp://HOST:8786")
    scheme, sep, rest = value.partition("://")
    if not sep:
        scheme, rest = "tcp", value
    if scheme.lower() != "tcp":
        raise refuse(
            f"the scheme {scheme!r} is not a Dask scheduler's; give tcp://HOST:PORT (the "
            "scheduler prints it: tcp://HOST:8786; 8787 is its dashboard)"
        )
    m = re.fullmatch(r"\[([0-9A-Fa-f:.%a-zA-Z]+)\]:(\d{1,5})", rest) or re.fullmatch(
        r"([A-Za-z0-9](?:[A-Za-z0-9.\-_]{0,252}[A-Za-z0-9])?):(\d{1,5})", rest
    )
    if not m:
        raise refuse("expected tcp://HOST:PORT (an IPv6 address in brackets: tcp://[::1]:8786)")
    host, port = m.group(1), int(m.group(2))
    if not 1 <= port <= 65535:
        raise refuse(f"port {port} is outside 1..65535")
    if rest.startswith("["):
        try:
            ipaddress.IPv6Address(host)
        except ValueError:
            raise refuse(f"{host!r} is not an IPv6 address") from None
        return SchedulerAddress(host, port, f"tcp://[{host}]:{port}")
    return SchedulerAddress(host, port, f"tcp://{host}:{port}")


def _receive(sock: socket.socket, n: int, deadline: float) -> bytes:
    data = b""
    while len(data) < n:
        left = deadline - time.monotonic()
        if left <= 0:
            raise TimeoutError
        sock.settimeout(left)
        chunk = sock.recv(n - len(data))
        if not chunk:
            break
        data += chunk
    return data


def probe_scheduler(address: SchedulerAddress, timeout: float = CONNECT_TIMEOUT_S) -> None:
    """Connect to ``address`` and check that it greets as a Dask scheduler does, within
    ``timeout`` seconds (connecting and reading each).

    A Dask scheduler sends its handshake first: a little-endian 8-byte length, then that
    many bytes (a count of frames, their lengths, and a msgpack map with ``python`` and
    ``pickle-protocol``). Anything else is refused before a Dask client reads from it.

    Parameters
    ----------
    address : SchedulerAddress
    timeout : float

    Raises
    ------
    UserInputError
        The host cannot be resolved, nothing listens there, it does not answer in time, or
        it answers something that is not a Dask handshake.
    """

    def refuse(reason: str) -> UserInputError:
        return UserInputError(f"--scheduler {address.url}: {reason}")

    try:
        sock = socket.create_connection((address.host, address.port), timeout=timeout)
    except socket.gaierror as exc:
        raise refuse(f"cannot resolve the host ({exc.strerror})") from None
    except ConnectionRefusedError:
        raise refuse("nothing listens there (connection refused)") from None
    except TimeoutError:
        raise refuse(f"no connection within {timeout:g} s") from None
    except OSError as exc:
        raise refuse(f"cannot connect ({exc.strerror or exc})") from None
    not_dask = (
        "not a Dask scheduler (is it the dashboard, 8787, or another service? the "
        "scheduler's address is tcp://HOST:8786 unless it was started with another port)"
    )
    with sock:
        deadline = time.monotonic() + timeout
        try:
            head = _receive(sock, 8, deadline)
            if len(head) < 8:
                raise refuse(f"it closed the connection without a Dask handshake: {not_dask}")
            (size,) = struct.unpack("<Q", head)
            if head.startswith(b"HTTP") or not 16 <= size <= _MAX_HANDSHAKE:
                what = "HTTP" if head.startswith(b"HTTP") else "something else"
                raise refuse(f"it answered {what}: {not_dask}")
            body = _receive(sock, size, deadline)
        except TimeoutError:
            raise refuse(f"it sent no Dask handshake within {timeout:g} s: {not_dask}") from None
        except OSError as exc:
            raise refuse(f"the connection failed ({exc.strerror or exc})") from None
    if len(body) < size or not _is_handshake(body):
        raise refuse(f"it answered something else than a Dask handshake: {not_dask}")


def _is_handshake(body: bytes) -> bool:
    """The frames of a Dask handshake: a count, the frame lengths adding up, the keys."""
    (count,) = struct.unpack_from("<Q", body)
    if not 1 <= count <= 16 or len(body) < 8 * (1 + count):
        return False
    lengths = struct.unpack_from(f"<{count}Q", body, 8)
    return sum(lengths) == len(body) - 8 * (1 + count) and all(
        key in body for key in (b"pickle-protocol", b"python")
    )


# ---------------------------------------------------------------------------------- workers
def usable_cpus() -> int:
    """CPUs this process may run on (its affinity, else the machine's count).

    Returns
    -------
    int
    """
    try:
        return len(os.sched_getaffinity(0)) or 1
    except (AttributeError, OSError):
        return os.cpu_count() or 1


def available_memory() -> int | None:
    """Bytes of memory available without swapping (``MemAvailable``).

    Returns
    -------
    int or None
        None where it cannot be read.
    """
    try:
        with open("/proc/meminfo", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (AttributeError, OSError, ValueError):
        return None


def check_workers(workers: int) -> int:
    """Refuse a worker count the machine cannot run: more than its usable CPUs (the tasks
    are CPU-bound: more processes only add memory) or than its memory holds
    (:data:`WORKER_BYTES` each).

    Parameters
    ----------
    workers : int

    Returns
    -------
    int
        ``workers``.

    Raises
    ------
    UserInputError
    """
    cpus = usable_cpus()
    memory = available_memory()
    by_memory = max(1, memory // WORKER_BYTES) if memory is not None else cpus
    bound = min(cpus, by_memory)
    if not 1 <= workers <= bound:
        why = f"{cpus} usable CPU{'s' if cpus > 1 else ''}"
        if by_memory < cpus:
            why += f" and memory for {by_memory} ({_bytes(memory)} available, about "
            why += f"{_bytes(WORKER_BYTES)} per worker)"
        raise UserInputError(f"--workers {workers}: give 1..{bound} (this machine has {why})")
    return workers


# ------------------------------------------------------------------------------------- grid
@dataclass(frozen=True)
class GridCost:
    """What a sweep will take: ``points``, ``chunks``, ``memory`` (bytes, peak of the client),
    ``disk`` (bytes of float results, which hardly compress), ``seconds`` (a lower bound:
    every point at least as dear as resolving the first one, on ``workers`` processes)."""

    points: int
    chunks: int
    memory: int
    disk: int
    seconds: float
    workers: int


def _bytes(n: float | None) -> str:
    if n is None:
        return "unknown"
    for unit in ("B", "kB", "MB", "GB", "TB", "PB"):
        if n < 1000 or unit == "PB":
            return f"{n:.3g} {unit}"
        n /= 1000
    return f"{n:.3g} PB"  # pragma: no cover


def _duration(s: float) -> str:
    if s < 120:
        return f"{s:.3g} s"
    if s < 7200:
        return f"{s / 60:.3g} min"
    if s < 2 * 86400:
        return f"{s / 3600:.3g} h"
    return f"{s / 86400:.3g} days"


def check_grid_cost(cost: GridCost, store: Path | None = None) -> None:
    """Refuse, before any work, a grid beyond the machine: more memory than is available,
    more disk than is free where the store goes, or a least time beyond
    :data:`MAX_SWEEP_DAYS`. The message gives the numbers.

    Parameters
    ----------
    cost : GridCost
    store : Path, optional
        Where the store goes (its nearest existing folder's free space is compared).

    Raises
    ------
    UserInputError
    """
    memory = available_memory()
    free = None
    if store is not None:
        folder = store
        while not folder.exists() and folder != folder.parent:
            folder = folder.parent
        try:
            free = shutil.disk_usage(folder).free
        except OSError:
            free = None
    problems = []
    if memory is not None and cost.memory > memory:
        problems.append(f"memory ({_bytes(memory)} available)")
    if free is not None and cost.disk > free:
        problems.append(f"disk ({_bytes(free)} free)")
    if cost.seconds > MAX_SWEEP_DAYS * 86400:
        problems.append(f"time (at most {MAX_SWEEP_DAYS} days)")
    if problems:
        raise UserInputError(
            f"a grid of {cost.points:,} points in {cost.chunks:,} chunks needs about "
            f"{_bytes(cost.memory)} of memory, {_bytes(cost.disk)} of disk and at least "
            f"{_duration(cost.seconds)} on {cost.workers} worker{'s' if cost.workers > 1 else ''}"
            f": beyond this machine's {' and '.join(problems)}; use fewer points, larger chunks "
            "or split the sweep"
        )
