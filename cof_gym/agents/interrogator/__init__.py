"""The learned interrogator: a torque climb steered by a learned filter of the sensor history.

**What it reads.** Only sensor observations: per window the phase lag of the wheelset speed behind
the modulated torque and its standard error, the compliance (speed/torque amplitude ratio), the
measured CoA, the applied DC torque, amplitude and frequency, the measured speed and normal load, and
the vehicle configuration it was built for (counter torque on or off, known on board), and the measured
creepage only through *differences between windows, in ratio*: a train's creepage carries a systematic
offset of the size of the peak creepage (reference speed and wheel radius errors) and a scale error of
a percent or two; the offset cancels in a difference, the scale in a ratio of two differences. It
never reads ``info["ground_truth"]``.

**The learned filter.** An ensemble of small heteroscedastic networks
(:class:`FilterEnsemble`, trained by :mod:`cof_gym.agents.interrogator.training` on the v2
randomisation: creep-law families and shapes, systematic sensor errors, speeds, loads, both vehicle
configurations) maps the episode's features (:class:`EpisodeFeatures`: the window's phase, compliance,
slope index ``ln cot(phase)`` and their change since the first driven window, the CoA and torque
growth, the secant flexibility of the creep curve ``d creepage / d CoA`` over the last step relative to
its chord from the first driven window, the quadratic-peak extrapolation of the CoA from the slopes of
the last windows (:func:`peak_gap`, from the phase and from the compliance), the two previous
windows) to two Gaussian predictions:

- the **headroom** ``ln(M_sat / DC)``: how far the DC torque is below the saturation torque;
- the **correction** ``ln(CoF / CoA)``: the factor from the measured CoA to the CoF.

The phase lag goes to 90 deg as the creep curve flattens (the paper's Eq. 3: the lag is
``atan(I w v / (k r^2))`` for the half wheelset, ``k`` the local slope), so the slope index falls as the
operating point nears the peak; the filter learns how far the peak still is from how the slope has
fallen, across the shapes it was trained on.

**The climb.** From the shared safe first step (below the lowest saturation torque in range), each
window moves the DC torque to ``DC x exp(min(h - target_headroom, max_log_step))`` (or, far from the
peak, up to ``approach_fraction`` of the gap ``h - target_headroom``) with the cautious
headroom ``h = mean - caution x std - spread_caution x spread`` (``std``: the ensemble's spread and each
member's predicted variance combined; ``spread``: the members' disagreement alone, which grows where
the readings are unlike the training climbs'; ``spread_caution`` 0 unless chosen), the modulation a fixed fraction of the DC. Where that gap is closed while the predicted
headroom is still uncertain (its std above ``creep_while_std``), it creeps by ``creep_log_step``: a
stop there would report a poorly known estimate, and a slow probe buys the readings that settle it;
with ``creep_sticky`` no later step is larger (the filter thought the peak might be near: a big step
after that passes the peak on a curve unlike its training curves), and with ``creep_release`` too
unless the cautious headroom has grown above it again (a false alarm: a climb held to the slow probe
from its second window on ends at the horizon far below the peak; the shipped climb's 0.45 since session 53, rule
94), or with ``creep_sticky_below`` only from a
slow-probe step the filter itself places near the peak (its mean headroom below that; rules 87-88, not adopted).
With ``creep_until`` the probe ends
once the predicted (mean) headroom is that low: the filter expects the peak within it, and each further
window there risks the modulation's crest passing the peak for readings the estimate no longer needs; with
``creep_cautious_floor`` (rule 89) also once the cautious headroom itself is below that floor: the steering
source's caution places the peak at the DC already, whatever its mean still says.
With ``pace_caution`` set, a slow-probe step (never a stop) is at least the horizon pace
(:meth:`ClimbParameters.pace_step`): the predicted headroom less that many stds, spread over the windows
left before the horizon; a probe that starts far below the peak of a curve the filter reads poorly (low
speeds, where Eq. 3's lag is small) otherwise ends at the horizon a factor of two or more below it.
With ``frequency_reference_m_s`` set, the modulation runs at ``frequency_hz x max(1, reference / v)`` (within the
drive's range; ``v`` the speed measured at the episode's start): Eq. 3's lag scales with ``w v``, and at a low
speed it stays flat until the slope has nearly vanished (:func:`speed_scaled_frequency`).
With ``floor_margin`` set, a step is at least the one that the lowest CoF the task admits
guarantees safe (:func:`floor_headroom`: the CoA is the DC's fraction of the saturation torque times
the CoF, so ``ln(CoF_min / CoA)`` bounds the headroom from below whatever the creep curve): a climb that
starts far below a high CoF's peak crosses that range in one step instead of spending windows there.
It stops (and reports ``CoA x exp(correction)``) when the next step would be smaller than
``min_log_step``, when the CoA falls although the torque rose (past the peak), at the drive's limit,
or one window before the horizon; with ``knee_stop`` also at a window whose lag jumps over the previous
window's as the phase rule's test has it (:meth:`ClimbParameters.knee_stops`; ``"slow_probe"``: only once
the climb has crept), reporting there what it reports at a headroom stop; with ``ceiling_stop`` also at the
window where the crest falls under a rising torque crest (:class:`~cof_gym.agents.runaway.CrestCeiling`),
reporting the same (with ``ceiling_fall_z`` a crest fall counts for both only beyond that many standard errors of
the two crests' difference: :attr:`~cof_gym.agents.runaway.CrestCeiling.fall_z`; with ``ceiling_near_headroom``
too, any fall counts where the predicted headroom is at most that; with ``ceiling_noise_z`` a fall counts only beyond
that many more standard errors per unit of read noise ratio above 1: :meth:`ClimbParameters.fall_margin`). The
climb probes on past a headroom stop with ``crest_probe_lag_rise_deg`` set, at ``creep_log_step``, while its lag has
risen that much since its first driven window and its crest still rises (:meth:`ClimbParameters.probes_on`; with
``crest_probe_max_lag_deg`` and ``crest_probe_max_lag_step_deg`` only below that lag and that lag's step; with
``crest_probe_max_noise_ratio`` only where its first windows read at most that ratio of the reference noise; with
``crest_probe_hold_crest`` under the torque crest of the window it started from, its modulation shrinking as the DC
rises: :meth:`ClimbParameters.held_crest_ratio`). With
``torque_balance`` the climb divides every torque reading by the gain its first driven window's torque balance
reads against the force channel (:func:`~cof_gym.agents.interrogator.readings.torque_balance_gain`: the mean torque
over the measured creep force times the wheel radius, ``(1 + e_T) / (1 + e_F)`` on a wheelset at a steady creepage),
so that the compliance carries the force gain's error instead of the torque gain's; with
``torque_balance_max_lag_deg`` only where that window's lag is at most that (a wheel settled within the window: its
time constant is ``tan(lag) / (2 pi f)``). The
climb follows the noise its sensors read with ``noise_reference_nms`` set: where the median of
:attr:`Reading.lockin_noise_nms` over its first :data:`NOISE_WINDOWS` driven windows (the wheel-speed noise the
lock-in fit reads, whatever the operating point) is ``r`` times that reference with ``r`` above 1, its cautions
are ``r ** -noise_caution_exponent`` and its slow probe's ``creep_while_std`` ``r ** noise_creep_exponent``
times the climb's (:meth:`ClimbParameters.at_noise`): networks fitted on sensors up to the reference's noise
predict a wider headroom spread from noisier readings, and a constant caution spends it in slowness. The
estimate is the filter's (the last rising window's CoA times its
predicted correction), or the best CoA of the climb times a factor, or the same CoA times the guards'
correction or the filter's and the guards' corrections pooled (inverse-variance weighted,
:func:`pooled_correction`), or the pooled one where the climb stops on its headroom and the filter's
otherwise, or an estimator's (below), whichever the validation chose. The parameters are chosen on validation scenarios only
(``experiments/train_interrogator.py``).

**Guards.** With ``guards`` (further ensembles that read their own feature blocks, e.g. networks fitted
on the measured creepage's modulation) the climb steers by the lowest cautious headroom of the filter
and its guards, each with its own std and spread (and, with ``guard_cautions``, its own caution in place of
``caution``): a guard can only slow the climb, and the estimate stays
the filter's unless ``estimate_from`` reads the guards' (:data:`GUARDED_ESTIMATES`). A directory's
``manifest.json`` names its guards (``"guards"``: directories of ``member_*.npz``, relative to it); the shipped
interrogator has two since session 31: ``guard_0``, the same networks fitted on the family climbs, on
procedural creep curves and on the climbs of the agent shipped before session 30, on the env's draws; and
``guard_1``, fitted on the first two alone (the probing guard, its only guard from session 16 to 30).
Since session 32 the shipped estimate pools both guards' corrections at every window, without the filter's
(session 31: the filter's and both guards').

**Estimators.** With ``estimators`` (further ensembles fitted on the deployed climb's own windows, on
policy: :func:`~cof_gym.agents.interrogator.training.collect` with a ``policy``) the estimate may read
their correction (``estimate_from="estimator"``), or theirs, the filter's and the guards' pooled
(``"estimator_pooled"``), or that pool where the climb stops on its headroom and the filter's otherwise
(``"estimator_pooled_at_headroom"``), or theirs alone there (``"estimator_at_headroom"``), or theirs and the
guards' pooled without the filter's (``"guard_estimator_pooled"``; :data:`ESTIMATOR_ESTIMATES`). They never steer:
the climb, and every macro-slip, is the same with or without them. The filter and the guards learn from random probing
climbs, so that no schedule leaks the truth into their features; an estimator learns the correction
where the deployed climb actually stops. A manifest names them under ``"estimators"``.

**A crest floor.** With ``crest_floor`` the reported estimate is at least the climb's best crest bound:
over its windows, the largest crest of the measured CoA's synchronous average over the modulation cycle
(``info["measurement"]["coa_cycle_max"]``) less one phase bin's standard error
(:attr:`Reading.crest_bound`). The crest is the adhesion at the torque's crest; it cannot exceed the
creep curve's peak, the CoF, and where the crest of a 40 % modulation has reached into the knee it is
much nearer the CoF than the window's mean CoA. It changes no step of the climb.
With ``crest_ceiling``, once a window's crest has fallen below the previous window's while its commanded
torque crest rose (:class:`~cof_gym.agents.runaway.CrestCeiling`: the crest has reached the peak), every
estimate is also at most the best crest plus one bin's standard error. It changes no step either.

**The estimate a runaway would report.** The env scores the estimate of a window that is not a stop
only if the wheel runs away in it (a macro-slip). With ``runaway_estimate`` that estimate is what such a
runaway measures (:class:`~cof_gym.agents.runaway.RunawayBracket`): the creep curve's peak lies above the
climb's best crest bound ``c`` (survived) and below what the coming window's torque crest demands, about
``c x rho`` for ``rho`` the ratio of that crest to the crest of the window that gave ``c`` (commanded
torques: the torque gain error cancels); the reported estimate is the bracket's geometric middle
``c sqrt(rho)``, whose largest log error over the bracket is the smallest. A stop reports the estimate of ``estimate_from`` as
before. It changes no step of the climb, and no estimate of an episode that does not run away.

**A crest cap.** With ``crest_fraction`` set, the modulation shrinks as the climb nears the peak: the
ratio of each window is at most ``exp(crest_fraction x h) - 1`` for the cautious headroom ``h`` left
after the step (:meth:`ClimbParameters.crest_ratio`, at least :data:`CREST_RATIO_FLOOR`), so that the
crest ``DC (1 + ratio)`` stays that fraction of the way to the cautiously predicted saturation torque: on
a creep curve that falls steeply past its peak, a 40 % crest passing the peak lets the wheel run away
before any reading shows the peak (the paper's outlook: interrogation at lower magnitudes of torque). Its
networks should be fitted on climbs whose modulation shrinks too (``ClimbDraws.crest_powers``). With
``crest_below_m_s`` the cap holds only in climbs whose starting speed is below it (a crest's excess torque spins a
slow wheel further; docs/interrogator.md, session 76: the slow family climbs lose what the slow steep ones gain).

**Two tones.** With ``tone2_frequency_hz`` set, the modulation is two sines (the env's
``excitation="multitone"``, ``tones=2``; :attr:`LearnedInterrogator.env_options`, which
``cof-gym evaluate`` applies to the agent's own env): tone 1 at ``frequency_hz`` and tone 2 with
``tone2_weight / (1 + tone2_weight)`` of the amplitude, each read by its own lock-in. The lag rises
with the frequency (Eq. 3: ``tan(lag) = I w v / (k r^2)`` grows with ``w``), so a second, higher tone reads
the slope's fall where one tone's lag is still small (low speeds, far from the peak), and the two lags'
ratio tells the wheel's first-order response from the drive's and suspension's; the filter then reads
:data:`TONE2_FEATURE_NAMES` as well and must be fitted on two-tone climbs.

**Feature blocks.** Beyond :data:`FEATURE_NAMES` a filter may read optional blocks
(:data:`FEATURE_BLOCKS`; its file names them, :func:`blocks_of`): ``tone2`` (above) and
``creepage_rise``, the measured creepage's rise since the first driven window itself, not only in
ratio (:data:`CREEPAGE_RISE_FEATURE_NAMES`): the offset cancels in the difference, and a scale error of a
percent or two moves its ``ln`` by 0.01-0.02, so the rise tells a long, flat knee (wet and
low-adhesion curves peak at large creepages) from a peak that is near. ``cycle_crest`` reads the measured
CoA's synchronous average over the cycle (:data:`CYCLE_CREST_FEATURE_NAMES`): how far its crest and
trough lie from the mean, their asymmetry (a crest that reaches the knee is clipped, the trough is not),
the crest's lift per lift of the torque's crest, the climb's best crest bound over the CoA (a lower bound
on the correction) and the crest's step since the previous window; a filter that reads it must be
fitted on climbs collected with that reading (session 22 on). ``climb_fit`` regresses over the climb's
newest windows (:data:`CLIMB_FIT_FEATURE_NAMES`): the slope's fall per log torque, the quadratic-peak
gap and the creep curve's flexibility fitted over up to :data:`CLIMB_FIT_WINDOWS` windows rather than
read from two, so that a slow probe's many readings of nearly one slope average out. ``torque_free``
appends nothing: it leaves out every feature that reads the compliance
(:data:`TORQUE_READING_FEATURE_NAMES`), the speed amplitude over the measured torque amplitude, so that the
network cannot see the torque sensor's gain error (a noise reading that cancels it too:
``ClimbParameters.noise_torque_measured``). ``applied_amplitude`` reads the modulation the drive applied over
the DC (the measured torque amplitude, :data:`APPLIED_AMPLITUDE_FEATURE_NAMES`) in place of the commanded
``amplitude_ratio``: a lagging drive applies less than it is asked for, and the crest reaches less far.

**An interval around the estimate.** A policy directory may hold ``interval.json`` (:class:`IntervalScales`):
scales calibrated by split conformal prediction on the validation grids' climbs, per way the estimate was
committed (:attr:`LearnedInterrogator.commitment`), in stds of the estimate's source correction (:attr:`LearnedInterrogator.estimate_log_std`). :meth:`LearnedInterrogator.cof_interval`
gives the two-sided interval and :meth:`LearnedInterrogator.cof_lower_bound` a lower bound on the CoF (an
over-estimate is the unsafe side for braking). Before the stop, :meth:`LearnedInterrogator.in_flight_interval`
and :meth:`LearnedInterrogator.in_flight_lower_bound` do the same for the estimate the windows read so far give
(:attr:`LearnedInterrogator.in_flight_estimate`), at scales of their own per place in the climb
(:attr:`LearnedInterrogator.in_flight`). A climb whose first windows read more noise than the v2 draws give
(:attr:`LearnedInterrogator.noisy`), or a smoothed encoder (:meth:`LearnedInterrogator.sensor_notes`), reads the
scales of its sensor class (:attr:`LearnedInterrogator.sensor_class`, :attr:`LearnedInterrogator.interval_group`),
calibrated on validation climbs played past the draws' noise, or with the encoder lagged. None of them changes the
climb or the estimate.

**A caution policy.** A policy directory may also name ``caution_policy.npz`` in its manifest (:class:`CautionPolicy`,
learnt by PPO in ``experiments/learned_caution.py``): a small network that sets the caution of each decision, filter
and guards, to ``caution x exp(CAUTION_SPAN a)`` from :meth:`LearnedInterrogator.climb_state`, what the climb decided
after its last window (:func:`cautioned`). The shipped directory carries none (rules 104-105).

**Sensor notes.** After an episode, :meth:`LearnedInterrogator.sensor_notes` names what the climb's own readings
say lies outside the sensors its networks were fitted on, without knowing the scenario: a smoothed encoder
(:data:`SMOOTHED_ENCODER`) where :func:`reads_smoothed_encoder` says so: the least :attr:`Reading.noise_colour` of
its first :data:`NOISE_WINDOWS` driven windows (:func:`first_windows_noise_colour`: the lag's SE for a first-order
autoregressive speed residual over its white-noise SE, about 1 for an encoder's white noise) above
:data:`~cof_gym.measurement.sine_fit.SMOOTHED_NOISE_COLOUR`, where those windows read sensor noise at all (at least
:data:`COLOUR_NOISE_FLOOR_NMS`). A smoothing adds its delay to every phase lag the networks read. Noisy sensors
(:data:`NOISY_SENSORS`) where the climb reads more noise than the v2 draws give (:attr:`LearnedInterrogator.noisy`,
whose interval takes the noisy scales). A slow drive
(:data:`SLOW_DRIVE`) where :func:`reads_slow_drive` says so: the drive's time constant read from the fraction of the
commanded modulation its first windows' torque readings measured (:func:`first_windows_drive_lag_s`,
:func:`drive_lag_s`: ``sqrt(1 / a^2 - 1) / (2 pi f)`` for a first-order drive) above :data:`SLOW_DRIVE_LAG_S`, past
every drive the networks were fitted on. ``cof-gym evaluate`` records the notes per episode and prints how many
episodes read each; the interval's sensor class reads the smoothed encoder and the noise, not the drive. A policy
directory may name networks of their own for a smoothed encoder's climb (its manifest's ``smoothed_encoder``:
:func:`manifest_smoothed_networks`, a :class:`NetworkSet` of a filter and as many guards as the climb's; with
``ClimbParameters.gate_max_drive_lag_s`` only behind a drive no slower than that): from the decision after its
:data:`NOISE_WINDOWS`-th driven window, where the note is final, they steer and estimate it in place of the climb's
own (:attr:`LearnedInterrogator.gated`; rule 127). Their features are read from the first window; every climb that
does not read a smoothed encoder, and every climb's first decisions, are as without them.

Two options change the estimate and no step of the climb (both off in the shipped climb, neither adopted):
``ClimbParameters.slow_drive_applied_estimate`` reads the estimate behind a slow drive from the same networks with
the modulation the drive applied in place of the commanded one (:meth:`EpisodeFeatures.vector` with
``applied_ratio``; rule 134), and ``ClimbParameters.relative_error_shift`` ``s`` reports ``CoA x exp(mean - s x
std^2)``, the minimiser of the expected relative error under the networks' posterior where ``s`` = 1 (0: its
median, what the reward's log error asks for).

**Modules**, each importing only those above it: :mod:`.readings` (one window's sensor readings, the slope
from Eq. 3), :mod:`.features` (the features of a climb's windows), :mod:`.networks` (the filter's networks
and their ensemble), :mod:`.interval` (the calibrated interval around the estimate), :mod:`.climb` (the
climb's settings and steps), :mod:`.caution` (the caution policy), :mod:`.agent` (the agent and its policy directory); :mod:`.training` (the training
climbs and the networks' fit: torch, imported on its own).
"""

from cof_gym.agents.interrogator.readings import (
    PHASE_CLIP_DEG, SE_CLIP_DEG, SE_REPORTED_MAX_DEG, NOISE_WINDOWS, COMPLIANCE_CLIP, slope_index, slope_from_phase,
    slope_from_compliance, Reading, first_windows_noise_nms, SMOOTHED_ENCODER, COLOUR_NOISE_FLOOR_NMS,
    first_windows_noise_colour, reads_smoothed_encoder, NOISY_SENSORS, SLOW_DRIVE, SLOW_DRIVE_LAG_S, drive_lag_s,
    first_windows_drive_lag_s, reads_slow_drive,
)
from cof_gym.agents.interrogator.features import (
    HISTORY, FEATURE_NAMES, TONE2_FEATURE_NAMES, CREEPAGE_RISE_FEATURE_NAMES, CREEPAGE_RISE_FLOORS,
    CREEPAGE_MODULATION_FEATURE_NAMES, CREEPAGE_SWING_FLOOR, CYCLE_CREST_FEATURE_NAMES, CYCLE_LIFT_FLOOR,
    CLIMB_FIT_FEATURE_NAMES, CLIMB_FIT_WINDOWS, CLIMB_FIT_MIN_SPAN, SLOPE_FALL_CLIP, TORQUE_READING_FEATURE_NAMES,
    APPLIED_AMPLITUDE_FEATURE_NAMES, BLOCK_LEAVES_OUT, FEATURE_BLOCKS,
    feature_names, blocks_of, FLEXIBILITY_CLIP, PEAK_GAP_CLIP, flexibility_ratio, slope_fall,
    fitted_peak_gap, fitted_flexibility, peak_gap, EpisodeFeatures,
)
from cof_gym.agents.interrogator.networks import (
    TARGET_NAMES, pooled_correction, pooled_std, FilterNetwork, FilterEnsemble,
)
from cof_gym.agents.interrogator.interval import (
    INTERVAL_FILE, COMMITMENTS, IN_FLIGHT, GROUPS, POOLED, POOLED_NOISY, POOLED_SMOOTHED, NOISY, SMOOTHED,
    SENSOR_CLASSES, FLOORED_CLASSES, CLASS_POOLS, NOISY_RATIO, LOG_STD_FLOOR, check_coverage, conformal_quantile,
    enough_for, sensor_group, noise_group, sensor_class_of, base_group, is_noisy, two_sided_score, lower_score,
    IntervalScales,
)
from cof_gym.agents.interrogator.climb import (
    ESTIMATE_SOURCES, HEADROOM_STOPS, AT_HEADROOM, KNEE_STOPS, GUARDED_ESTIMATES, ESTIMATOR_ESTIMATES,
    TWO_TONE_ENV_OPTIONS, CREST_RATIO_FLOOR, speed_scaled_frequency, floor_headroom, ClimbParameters,
)
from cof_gym.agents.interrogator.caution import (
    CAUTION_SPAN, CAUTION_POLICY_FILE, CLIMB_STATE_FIELDS, cautioned, CautionPolicy,
)
from cof_gym.agents.interrogator.agent import (
    SHIPPED_INTERROGATOR, WORLD_KWARGS, WindowDecision, NetworkSet, LearnedInterrogator, read_manifest, manifest_climb,
    write_manifest, manifest_networks, manifest_guards, manifest_smoothed_networks, interrogator_for, load_interrogator,
)

__all__ = [
    "PHASE_CLIP_DEG", "SE_CLIP_DEG", "SE_REPORTED_MAX_DEG", "NOISE_WINDOWS", "COMPLIANCE_CLIP", "slope_index",
    "slope_from_phase", "slope_from_compliance", "Reading", "first_windows_noise_nms",
    "SMOOTHED_ENCODER", "COLOUR_NOISE_FLOOR_NMS", "first_windows_noise_colour", "reads_smoothed_encoder",
    "NOISY_SENSORS", "SLOW_DRIVE", "SLOW_DRIVE_LAG_S", "drive_lag_s", "first_windows_drive_lag_s", "reads_slow_drive",
    "HISTORY",
    "FEATURE_NAMES",
    "TONE2_FEATURE_NAMES", "CREEPAGE_RISE_FEATURE_NAMES", "CREEPAGE_RISE_FLOORS",
    "CREEPAGE_MODULATION_FEATURE_NAMES", "CREEPAGE_SWING_FLOOR", "CYCLE_CREST_FEATURE_NAMES", "CYCLE_LIFT_FLOOR",
    "CLIMB_FIT_FEATURE_NAMES", "CLIMB_FIT_WINDOWS", "CLIMB_FIT_MIN_SPAN", "SLOPE_FALL_CLIP", "FEATURE_BLOCKS",
    "TORQUE_READING_FEATURE_NAMES", "APPLIED_AMPLITUDE_FEATURE_NAMES", "BLOCK_LEAVES_OUT",
    "feature_names", "blocks_of", "FLEXIBILITY_CLIP", "PEAK_GAP_CLIP",
    "flexibility_ratio", "slope_fall",
    "fitted_peak_gap", "fitted_flexibility", "peak_gap", "EpisodeFeatures", "TARGET_NAMES", "pooled_correction",
    "pooled_std", "FilterNetwork", "FilterEnsemble", "INTERVAL_FILE", "COMMITMENTS", "IN_FLIGHT", "GROUPS", "POOLED", "LOG_STD_FLOOR",
    "POOLED_NOISY", "POOLED_SMOOTHED", "NOISY", "SMOOTHED", "SENSOR_CLASSES", "FLOORED_CLASSES", "CLASS_POOLS",
    "NOISY_RATIO",
    "sensor_group", "noise_group", "sensor_class_of", "base_group", "is_noisy",
    "check_coverage", "conformal_quantile", "enough_for", "two_sided_score", "lower_score", "IntervalScales", "ESTIMATE_SOURCES", "HEADROOM_STOPS", "AT_HEADROOM", "KNEE_STOPS",
    "GUARDED_ESTIMATES", "ESTIMATOR_ESTIMATES", "TWO_TONE_ENV_OPTIONS", "CREST_RATIO_FLOOR",
    "speed_scaled_frequency", "floor_headroom", "ClimbParameters", "SHIPPED_INTERROGATOR", "WORLD_KWARGS",
    "WindowDecision", "NetworkSet", "LearnedInterrogator", "read_manifest", "write_manifest", "manifest_climb",
    "manifest_networks",
    "manifest_guards", "manifest_smoothed_networks", "interrogator_for", "load_interrogator", "CAUTION_SPAN",
    "CAUTION_POLICY_FILE", "cautioned",
    "CautionPolicy", "CLIMB_STATE_FIELDS",
]
