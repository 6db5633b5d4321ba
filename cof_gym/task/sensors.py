"""Systematic sensor errors: what a train's sensors read when their calibration is off.

Random noise is added per physics step by the native measurement chain
(:class:`cof_gym.physics.simulation.SensorNoise`). A train's sensors also carry *systematic* errors
that stay constant over a measurement; they are drawn once per episode (v2) and change what the
sensors read, never the physics. Each is a relative error ``e``: the sensor reads ``(1 + e)`` times
the true value.

=========================== ========== ========== =====================================================
field                        drawn (v2)  accepted   what it models, source
=========================== ========== ========== =====================================================
``speed_sensor_error``       +-1.5 %     +-5 %      the reference (train) speed. A state-of-the-art
                                                    correlation radar reached a peak error of 0.47 km/h
                                                    up to 130 km/h (Reissland, Weigel, Koelpin, Lurz,
                                                    IEEE MTT-S featured article, Dec 2023): 1.3 % at
                                                    36 km/h, 2.6 % at 18 km/h; other sources
                                                    (unpowered axles, GNSS) are no better
``wheel_radius_error``       +-0.5 %     +-2 %      the rolling radius the creepage computation
                                                    assumes, drifting with tread wear between
                                                    calibrations: 1 mm of wear on 460 mm is 0.22 %
``force_gain_error``         +-1 %       +-10 %     gain of the tangential-force measurement
                                                    (a calibrated instrumented wheelset or a force
                                                    observer): cof_gym's choice, a calibration
                                                    uncertainty of about a percent (unverified); it
                                                    scales every measured CoA, so it is a floor no
                                                    agent can measure below
``torque_gain_error``        +-5 %       +-15 %     gain of the drive's torque estimate (motor-current
                                                    torque model): cof_gym's choice (unverified)
=========================== ========== ========== =====================================================

How each reading changes (``s`` the creepage the sensors would read without systematic error):
creepage ``(1 + s)(1 + e_R) / (1 + e_v) - 1`` (the train computes ``R Omega / v - 1`` with the assumed
radius and the reference speed), speed ``(1 + e_v) v``, tangential force and measured CoA (its window
mean and its cycle's synchronous average) ``(1 + e_F)``, torque readings ``(1 + e_T)`` and the
speed/torque amplitude ratio ``/ (1 + e_T)``. The phase lag is a ratio of two fitted phases and no
gain changes it: the paper's point about the phase method. Every map is affine in the window's mean
(and a gain on a phase bin's mean), so applying it to the window's averages is exactly what applying
it to every sample would give.

One systematic error is not a gain: the **encoder's speed-signal lag** (``encoder_lag_s``, a scenario field in
[0, 0.05] s; v1 and v2 read the encoder without lag, v3 draws 0-5 ms). A wheel's speed is estimated from an
encoder's pulses (counted over a gate time or timed between edges) and smoothed before the drive or a
wheel-slide protection reads it; cof_gym models that as a first-order lag of time constant ``tau`` on the
encoder's reading, run per physics step in the native measurement chain (``y += (1 - exp(-dt / tau)) (x - y)``,
``x`` the mean of the step's reading and the last, so that the lag delays by ``tau``; from the first reading). At
the modulation frequency ``w`` it adds ``atan(w tau)`` to every phase lag the lock-in reads between the torque and
the speed (9 deg at 5 Hz with 5 ms, 17 deg with 10 ms) and scales the compliance by
``1 / sqrt(1 + (w tau)^2)``; the window means and the physics are unchanged. A phase method is exposed to exactly
this error, which no gain calibration removes: the paper's rule (stop at the first positive phase) reads a lag
that is ``atan(w tau)`` too large everywhere, while a rule that reads the lag's rise within the climb at a fixed
frequency does not see the offset. It does see the smoothing's other effect: the speed fit's residual is no longer
white, so the lock-in's white-noise SE of the lag (``phase_lag_se_deg``) understates the lag's scatter, several
times over at 10 ms; ``phase_lag_se_corrected_deg`` is the SE for a first-order autoregressive residual (its lag-1
correlation read in the window). The range is cof_gym's choice (unverified): from no smoothing through a light one
(5 ms: a 32 Hz cut-off) to a sluggish one (50 ms: 3 Hz).

Nor does any draw read the wheelset's speed from a **speed probe's pulses** (``encoder_pulses_per_rev``) or give its
target wheel a **runout** (``encoder_runout``): both are scenario fields, 0 unless fixed, modelled with their sources
in :mod:`cof_gym.physics.encoder`. The pulses' period method delays the reading by about one interval between
pulses (a lag of ``360 f T_p`` degrees that grows as the train slows); a runout adds a ripple at the wheelset's
rotation frequency, which no gain calibration removes either and which a lock-in near that frequency reads.

The drive applies the commanded torque and its reading carries the gain, so in cof_gym the torque gain
error shows as the ratio of the mean torque reading to the command. A real drive that controls on its own
torque estimate would apply ``command / (1 + e)`` and read its command back, so that ratio is this
model's, not a train's: the learned interrogator reads torque through the amplitude ratio (and, with
``ClimbParameters.noise_torque_measured`` and ``lag_floor``, off in the shipped climb, the amplitude reading), never
the mean torque against its command. With ``ClimbParameters.torque_balance`` (off by default, on in the shipped
policy's manifest) it reads the mean torque against the measured creep force instead: on a wheelset at a steady creepage the drive
torque is the creep force times the wheel radius, so the ratio of the two readings is ``(1 + e_T) / (1 + e_F)``,
a calibration a train with a force measurement can make too. In cof_gym the wheel rolls on its nominal radius (the
radius error is the creepage computation's), so the balance carries no radius error; a train's would carry its
assumed radius's (``wheel_radius_error``'s range).
"""

from __future__ import annotations

from dataclasses import dataclass, fields, replace
from types import MappingProxyType
from typing import Mapping

from cof_gym.physics.simulation import COA_CYCLE_FIELDS, WindowMeasurement, tone_field


@dataclass(frozen=True)
class ErrorRange:
    """A systematic error's default draw (uniform in +-``drawn``) and the values accepted when fixed."""

    drawn: float
    accepted: float


# the one table of systematic errors: field -> ranges (the docstring above gives the sources)
SYSTEMATIC_ERRORS: Mapping[str, ErrorRange] = MappingProxyType({
    "speed_sensor_error": ErrorRange(drawn=0.015, accepted=0.05),
    "wheel_radius_error": ErrorRange(drawn=0.005, accepted=0.02),
    "force_gain_error": ErrorRange(drawn=0.01, accepted=0.10),
    "torque_gain_error": ErrorRange(drawn=0.05, accepted=0.15),
})


@dataclass(frozen=True)
class SensorErrors:
    """One episode's systematic sensor errors (relative, see the module table)."""

    speed_sensor_error: float = 0.0
    wheel_radius_error: float = 0.0
    force_gain_error: float = 0.0
    torque_gain_error: float = 0.0

    @property
    def creepage_offset(self) -> float:
        """The systematic creepage error at zero creepage, (1 + e_R) / (1 + e_v) - 1 (about e_R - e_v)."""
        return (1.0 + self.wheel_radius_error) / (1.0 + self.speed_sensor_error) - 1.0

    @property
    def is_zero(self) -> bool:
        return not any(getattr(self, f.name) for f in fields(self))

    def read(self, m: WindowMeasurement) -> WindowMeasurement:
        """What the sensors read of the window ``m`` (its true values untouched); ``m`` itself without
        systematic errors, so v1 numbers stay bit-identical."""
        if self.is_zero:
            return m
        creep_gain = 1.0 + self.creepage_offset
        force_gain = 1.0 + self.force_gain_error
        torque_gain = 1.0 + self.torque_gain_error
        tones = {}
        for k in range(1, m.n_tones + 1):  # every tone's torque reads through the same gain
            amp, ratio = tone_field(k, "torque_amplitude_nm"), tone_field(k, "amplitude_ratio")
            tones[amp] = getattr(m, amp) * torque_gain
            tones[ratio] = getattr(m, ratio) / torque_gain
        return replace(
            m,
            **tones,
            creepage_measured=(1.0 + m.creepage_measured) * creep_gain - 1.0,
            creepage_modulation_amplitude=m.creepage_modulation_amplitude * creep_gain,
            speed_measured_m_s=m.speed_measured_m_s * (1.0 + self.speed_sensor_error),
            tangential_force_measured_n=m.tangential_force_measured_n * force_gain,
            coa_measured=m.coa_measured * force_gain,
            **{name: getattr(m, name) * force_gain for name in COA_CYCLE_FIELDS},
            torque_amplitude_nm=m.torque_amplitude_nm * torque_gain,
            torque_mean_nm=m.torque_mean_nm * torque_gain,
            torque_peak_nm=m.torque_peak_nm * torque_gain,
            amplitude_ratio=m.amplitude_ratio / torque_gain,
        )
