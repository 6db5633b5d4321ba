"""How many worker processes ``cof-gym evaluate`` starts: the cores the process may use (a container's CPU
quota included) and the memory each worker needs."""

from __future__ import annotations

import math
import os
from pathlib import Path

# a worker's start (imports, env, agents: a few seconds) costs about as much as this many episodes, so the default
# number of workers gives each at least this many
EPISODES_PER_WORKER = 40
MAX_WORKERS = 1024
WORKER_MEMORY_BYTES = 1 << 30  # memory a worker may take (measured: 0.41 GB resident with every default agent)


def _read(path: str) -> str:
    try:
        return Path(path).read_text()
    except OSError:
        return ""


def usable_cores() -> int:
    """The CPU cores this process may run on: its affinity, and a container's CPU quota where one is set
    (cgroup v2 ``cpu.max``: a container sees every core of its host but may use only its quota)."""
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
    quota, _, period = _read("/sys/fs/cgroup/cpu.max").partition(" ")
    if quota.strip().isdigit() and period.strip().isdigit() and int(period) > 0:
        cores = min(cores, max(1, math.ceil(int(quota) / int(period))))
    return cores


def available_memory_bytes() -> int | None:
    """Memory available to new processes (``MemAvailable`` of /proc/meminfo); None where it cannot be read."""
    for line in _read("/proc/meminfo").splitlines():
        name, _, value = line.partition(":")
        kib = value.split()[:1]
        if name == "MemAvailable" and kib and kib[0].isdigit():
            return int(kib[0]) * 1024
    return None


def fitting_workers(memory_per_worker: int) -> int:
    """Processes this machine holds: one a usable core, at most one per ``memory_per_worker`` bytes of the
    available memory (the cores alone where it cannot be read); at least 1."""
    cores, memory = usable_cores(), available_memory_bytes()
    return max(1, cores if memory is None else min(cores, memory // memory_per_worker))


def default_workers(n_episodes: int) -> int:
    """One worker a usable core, each with at least :data:`EPISODES_PER_WORKER` of the ``n_episodes``
    (every agent's together) to play and :data:`WORKER_MEMORY_BYTES` of the available memory; 1: the episodes
    are played in this process."""
    return max(1, min(fitting_workers(WORKER_MEMORY_BYTES), n_episodes // EPISODES_PER_WORKER))


def oversubscription_note(workers: int, n_episodes: int) -> str | None:
    """A one-line note where ``workers`` asked for (at most one an episode is started) exceed the usable cores: they
    are started as asked, share the cores and each pays its start-up; None where they fit."""
    started, cores = min(workers, n_episodes), usable_cores()
    if started <= cores:
        return None
    return (f"note: --workers {workers} starts {started} processes on the {cores} usable core(s): they share them and "
            f"each pays a start-up of a few seconds (the outputs are the same for any number; default: "
            f"{default_workers(n_episodes)} here)")
