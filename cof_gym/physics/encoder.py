"""The wheelset-speed encoder as a pulse generator: a toothed wheel read by a speed probe.

A train does not read its wheelset's spin rate continuously. A speed probe (Hall-effect or inductive) on the axle,
the gearbox or the motor shaft gives a pulse per tooth of a target wheel, "between 60 and 300 pulses per
revolution" depending on the target wheel's diameter and teeth for the two-channel probes that read a traction
drive's target wheel (Wikipedia, "Wheel speed sensor", section "Rail vehicles", as read in 2026; a probe on the
motor shaft gives that times the gear ratio per revolution of the wheelset). Traction and wheel-slide controllers
compute the speed from the pulses, here by the *period method*: each pulse is timestamped by a fast counter clock
(taken as exact: a MHz clock resolves a millisecond interval to about 1e-3 of it) and the reading is one pulse
pitch over the last complete interval between pulses, held until the next pulse.

Two properties of such a reading matter for a phase method:

* **Delay.** The reading is the mean spin rate over the last interval ``T_p = 2 pi / (N omega)`` and is held for
  up to another: on average it reads the spin rate of about ``T_p`` ago, a delay that grows as the train slows and
  adds about ``360 f T_p`` degrees to every phase lag the lock-in reads at the modulation frequency ``f`` (5.2 deg
  at 5 Hz with 100 pulses per revolution at 10 m/s on a 0.46 m wheel; 17 deg with 60 pulses at 5 m/s).
* **Runout.** A target wheel mounted off the axle's centre by ``epsilon`` (or with a once-per-revolution pitch
  error) gives its pulses at the apparent angle ``theta + e sin(theta)``, ``e = epsilon / r`` its runout relative
  to its pitch radius ``r``: the reading carries a ripple of ``e omega`` at the wheelset's rotation frequency
  ``omega / 2 pi`` (3.5 Hz at 10 m/s on a 0.46 m wheel), which passes through the modulation's band as the speed
  changes (5 Hz at 14.5 m/s). 0.1 mm of runout on a 100 mm target wheel is ``e`` = 0.1 %, a ripple of 0.02 rad/s at
  10 m/s: ten times a small modulation's response far below the creep peak.

The model runs in the native measurement chain once per physics step (``pulse_encoder`` in ``cofgym_native.c``):
the measured wheelset's angle integrated by the trapezoid rule from the reset (where ``theta`` = 0, the runout's
phase), each pulse's time interpolated linearly within the step, before two pulses the spin rate at the reset; the
drawn white noise and the encoder's lag (``encoder_lag_s``) then act on this reading as on the continuous one. It
counts forward rotation only (the task drives; a wheel turning back holds the reading). Without pulses a runout
acts on the continuous reading, ``omega (1 + e cos theta)`` (an angle sensor mounted off centre). ``pulses_per_rev``
0 with no runout is the continuous reading every v1 and v2 draw has, bit for bit (v3 draws 60-300 pulses and a
runout of 0-0.1 %: :data:`cof_gym.task.V3_RANGES`). The accepted ranges are cof_gym's
choice (unverified): 8 to 10000 pulses per revolution (a coarse axle probe to a motor-shaft encoder behind a gear),
runout up to 1 %.

The env argument ``lock_in="rotation"`` (:data:`cof_gym.physics.simulation.LOCK_INS`) takes the runout's ripple out of
the lock-in: it also fits the first two harmonics of the angle the encoder counts (its pulses times the pitch), of
which the reading's ripple is a function to the runout's third order. Where a harmonic's frequency is within about
0.44 / span of the modulation's (the wheel turning at 5 Hz at 14.5 m/s, at 2.5 Hz at 7.2 m/s on a 0.46 m wheel), the
window cannot tell it from the tone, and that window's fit leaves it out (a tone's coefficient variance would grow
more than twice, :data:`cof_gym.physics.simulation.MAX_ROTATION_INFLATION`): its ripple leaks into the lag there as
into the plain lock-in's, where fitting it would leave the lag no information. Cost: ``cof-gym bench``'s row "ratio
native with a pulse encoder read by the rotation lock-in / continuous encoder", 0.93-1.04 over four runs in session
83 (0.94 in the median).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from cof_gym.validation import check_int, check_number, is_int

PULSES_PER_REV_RANGE = (8, 10000)  # pulses per revolution of the wheelset a pulse encoder may give (0: continuous)
RUNOUT_MAX = 0.01  # the target wheel's runout over its pitch radius


def check_pulses_per_rev(name: str, value: object) -> int:
    """0 (a continuous reading) or an integer in :data:`PULSES_PER_REV_RANGE`; ``ValueError`` naming ``name``."""
    if is_int(value) and int(value) == 0:
        return 0
    low, high = PULSES_PER_REV_RANGE
    try:
        return check_int(name, value, low, high)
    except ValueError:
        raise ValueError(f"{name} must be 0 (a continuous reading) or an integer in [{low}, {high}], "
                         f"got {value!r} ({type(value).__name__})") from None


def check_runout(name: str, value: object) -> float:
    """A relative runout in [0, :data:`RUNOUT_MAX`]; ``ValueError`` naming ``name``."""
    return check_number(name, value, 0.0, RUNOUT_MAX)


@dataclass(frozen=True)
class PulseEncoder:
    """The wheelset-speed encoder: ``pulses_per_rev`` pulses per revolution of the wheelset (0: the continuous
    reading) and the target wheel's relative ``runout`` (a once-per-revolution ripple of ``runout`` x the spin rate,
    on the pulses or on the continuous reading)."""

    pulses_per_rev: int = 0
    runout: float = 0.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "pulses_per_rev", check_pulses_per_rev("pulses_per_rev", self.pulses_per_rev))
        object.__setattr__(self, "runout", check_runout("runout", self.runout))

    def pulse_interval_s(self, spin_rate_rad_s: float) -> float:
        """The time between two pulses at a steady spin rate (rad/s), s: the reading's delay, about one interval."""
        check_number("spin_rate_rad_s", spin_rate_rad_s, 0.0, math.inf, low_open=True, unit=" rad/s")
        if self.pulses_per_rev == 0:
            raise ValueError("a continuous reading (pulses_per_rev 0) has no pulse interval")
        return 2.0 * math.pi / (self.pulses_per_rev * spin_rate_rad_s)
