"""The torque-interrogation task (scenarios, ground truth, agent interface, reward, constraints),
independent of how the physics is stepped."""

from cof_gym.task.ground_truth import GroundTruth
from cof_gym.task.interface import (
    ACTION_NAMES, OBSERVATION_NAMES, SENSOR_FIELDS, DecodedObservation, MotorLimits, ObservationScales,
    decode_observation, encode_action,
)
from cof_gym.task.reward import MacroSlipLimit, Reward
from cof_gym.task.scenarios import COF_BY_CONDITION, COF_ENVELOPE, V2_RANGES, V3_RANGES, ScenarioRanges
from cof_gym.task.task import Episode, InterrogationTask

__all__ = [
    "ACTION_NAMES", "OBSERVATION_NAMES", "SENSOR_FIELDS", "COF_BY_CONDITION", "COF_ENVELOPE", "DecodedObservation",
    "Episode", "GroundTruth", "InterrogationTask", "MacroSlipLimit", "MotorLimits", "ObservationScales", "Reward",
    "ScenarioRanges", "V2_RANGES", "V3_RANGES", "decode_observation", "encode_action",
]
