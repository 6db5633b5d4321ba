"""Writes ``v3_summary.json``: fixed-seed trajectories of task v3 (``CofGym/TorqueInterrogationInService-v3``) that
``tests/test_v3_golden.py`` compares every later version of the code with (published v3 numbers must never change).
Run from the commit whose numbers are published::

    python tests/golden/make_v3_golden.py tests/golden/v3_summary.json

(written in session 86, when task v3 was added). The cases pass through what v3 adds to v2: the speed probe's pulses,
runout and lag and the track's irregularity drawn (both classes), a fixed probe and a smooth track, the counter torque,
the rotation lock-in, a stop and a climb into a macro-slip; the climb and what is kept per window are v2's
(``make_v2_golden.py``).
"""

from __future__ import annotations

import json
import sys

from make_v2_golden import trajectory

IN_SERVICE = "CofGym/TorqueInterrogationInService-v3"
CASES = {  # name -> (env id, constructor arguments, seed, reset options, stop at make_v2_golden.STOP_AT)
    "in_service/seed0": (IN_SERVICE, {}, 0, None, False),
    "in_service/seed1": (IN_SERVICE, {}, 1, None, False),
    "in_service/counter_torque/seed4": (IN_SERVICE, {"counter_torque": True}, 4, None, False),
    "in_service/rotation_lock_in/seed5": (IN_SERVICE, {"lock_in": "rotation"}, 5, None, False),
    "in_service/fixed_probe_smooth/seed6": (IN_SERVICE, {}, 6, {"encoder_pulses_per_rev": 100, "encoder_runout": 0.0005,
                                                                "track_irregularity": "smooth"}, False),
    "in_service/stop/seed7": (IN_SERVICE, {}, 7, None, True),
}


def summary() -> dict:
    return {name: trajectory(*case) for name, case in CASES.items()}


if __name__ == "__main__":
    with open(sys.argv[1], "w") as f:
        json.dump(summary(), f, indent=1)
