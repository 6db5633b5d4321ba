"""Scenery for the rendered models: sky, ground, ballast, sleepers, rails, lights, and wheels on the rails.

Everything here is visual only: world geoms and wheel dressings with ``contype = conaffinity = 0`` and
no mass (the bodies' inertias are explicit), lights, textures, materials and ``visual`` settings. The
wheel-rail forces are not MuJoCo contacts (see :mod:`cof_gym.physics.models`), so the dynamics do not
change; ``tests/test_watch.py`` checks a seeded episode is bit-identical with and without scenery.

The track is periodic along x with period :data:`TRACK_PERIOD_M` (sleepers, ground checker), so a
renderer may shift every scenery geom by a whole number of periods to keep a long run on the track.
"""

from __future__ import annotations

from collections.abc import Sequence

import mujoco
import numpy as np

GAUGE_M = 1.435  # standard gauge, between the rails' running edges
RAIL_HEAD_M = 0.07  # rail head width
RAIL_HEIGHT_M = 0.172  # UIC 60 rail height; the rail top is z = 0 (where the wheels run)
SLEEPER_SPACING_M = 0.6
SLEEPER_LENGTH_M = 2.6
TRACK_PERIOD_M = 10 * SLEEPER_SPACING_M  # the scenery repeats every 6 m along x
TRACK_START_M = -200.0
TRACK_LENGTH_M = 3000.0  # covers 30 windows of 1 s at 40 m/s with margin; renderers may shift it
SCENERY_PREFIX = "scenery_"  # name prefix of every world geom this module adds
_NO_CONTACT = {"contype": 0, "conaffinity": 0}


def _texture(spec: mujoco.MjSpec, name: str, rgb: np.ndarray) -> None:
    """A 2D texture from an (H, W, 3) array of values in [0, 1]."""
    data = np.ascontiguousarray(np.clip(rgb * 255.0, 0, 255).astype(np.uint8))
    tex = spec.add_texture(name=name, type=mujoco.mjtTexture.mjTEXTURE_2D, width=data.shape[1],
                           height=data.shape[0], nchannel=3)
    tex.data = data.tobytes()


def _material(spec: mujoco.MjSpec, name: str, texture: str | None = None, texrepeat=(1.0, 1.0),
              rgba=(1, 1, 1, 1), specular: float = 0.2, shininess: float = 0.2, reflectance: float = 0.0) -> str:
    mat = spec.add_material(name=name, rgba=list(rgba), specular=specular, shininess=shininess,
                            reflectance=reflectance, texrepeat=list(texrepeat), texuniform=True)
    if texture is not None:
        mat.textures[mujoco.mjtTextureRole.mjTEXROLE_RGB] = texture
    return name


def _add_textures(spec: mujoco.MjSpec) -> None:
    rng = np.random.default_rng(7)  # fixed: the same scenery in every build
    # ballast: grey-brown gravel speckle
    n = 64
    base = np.array([0.42, 0.39, 0.35])
    ballast = base * (0.7 + 0.6 * rng.random((n, n, 1)))
    _texture(spec, "scenery_ballast", ballast)
    # sleepers: concrete bands across the track on ballast, one sleeper per texture repeat (u along x)
    sleeper = ballast.copy()
    width = int(round(n * 0.26 / SLEEPER_SPACING_M))
    sleeper[:, :width] = np.array([0.66, 0.64, 0.6]) * (0.93 + 0.07 * rng.random((n, width, 1)))
    sleeper[:, width - 1] *= 0.6  # a shadowed edge
    _texture(spec, "scenery_sleepers", sleeper)
    # grass: green with a light checker every 3 m (a reference for the motion)
    grass = np.array([0.33, 0.45, 0.22]) * (0.8 + 0.35 * rng.random((n, n, 1)))
    grass[: n // 2, : n // 2] *= 1.12
    grass[n // 2:, n // 2:] *= 1.12
    _texture(spec, "scenery_grass", grass)
    spec.add_texture(name="scenery_sky", type=mujoco.mjtTexture.mjTEXTURE_SKYBOX,
                     builtin=mujoco.mjtBuiltin.mjBUILTIN_GRADIENT, rgb1=[0.55, 0.72, 0.92], rgb2=[0.95, 0.97, 1.0],
                     width=256, height=1536)


def _plane(spec: mujoco.MjSpec, name: str, z: float, half_width: float, material: str) -> None:
    half = TRACK_LENGTH_M / 2
    spec.worldbody.add_geom(name=SCENERY_PREFIX + name, type=mujoco.mjtGeom.mjGEOM_PLANE,
                            pos=[TRACK_START_M + half, 0, z], size=[half, half_width, 1.0], material=material,
                            **_NO_CONTACT)


def _dress_wheelset(spec: mujoco.MjSpec, body_name: str, radius: float, rail_y: Sequence[float],
                    highlight: bool) -> None:
    """Two wheels on the rails, flanges inside, an axle and a spoke mark per wheel (visual only)."""
    body = spec.body(body_name)
    cyl = mujoco.mjtGeom.mjGEOM_CYLINDER
    about_y = [0.7071068, 0.7071068, 0, 0]
    mark = [0.95, 0.35, 0.1, 1] if highlight else [0.85, 0.85, 0.8, 1]
    for y in rail_y:
        side = 1.0 if y >= 0 else -1.0
        tread_y = y + side * 0.04  # the tread's centre sits over the rail head, the flange inside
        body.add_geom(type=cyl, size=[radius, 0.065, 0], pos=[0, tread_y, 0], quat=about_y,
                      material="scenery_wheel", mass=0, **_NO_CONTACT)
        body.add_geom(type=cyl, size=[radius + 0.03, 0.0125, 0], pos=[0, tread_y - side * 0.0775, 0], quat=about_y,
                      material="scenery_wheel", mass=0, **_NO_CONTACT)
        body.add_geom(type=mujoco.mjtGeom.mjGEOM_BOX, size=[radius * 0.85, 0.004, 0.04],
                      pos=[0, tread_y + side * 0.066, 0], rgba=mark, mass=0, **_NO_CONTACT)
    if len(rail_y) > 1:
        body.add_geom(type=cyl, size=[0.085, (max(rail_y) - min(rail_y)) / 2, 0], quat=about_y,
                      material="scenery_wheel", mass=0, **_NO_CONTACT)


def add_scenery(spec: mujoco.MjSpec, wheel_radius_m: float, wheel_bodies: Sequence[str] = (),
                driven_body: str | None = None, rail_y_m: Sequence[float] = (-GAUGE_M / 2 - 0.035, GAUGE_M / 2 + 0.035)
                ) -> None:
    """Add the scenery to ``spec`` (call it after the vehicle's bodies, before compiling).

    ``rail_y_m``: the rails' centre lines, m (default: standard gauge); ``wheel_bodies`` get two wheels
    on them, ``driven_body`` with orange spoke marks. The model's visual statistics (extent and centre,
    which set the cameras' clip planes) stay those of the vehicle alone."""
    vehicle_stat = spec.compile().stat  # the vehicle's own view, before the long track enlarges it
    _add_textures(spec)
    _material(spec, "scenery_ballast", "scenery_ballast", texrepeat=(1 / 1.2, 1 / 1.2), specular=0.05)
    _material(spec, "scenery_sleepers", "scenery_sleepers", texrepeat=(1 / SLEEPER_SPACING_M, 1 / SLEEPER_LENGTH_M),
              specular=0.1)
    _material(spec, "scenery_grass", "scenery_grass", texrepeat=(1 / TRACK_PERIOD_M, 1 / TRACK_PERIOD_M),
              specular=0.02)
    _material(spec, "scenery_rail", rgba=(0.55, 0.52, 0.5, 1), specular=0.9, shininess=0.8)
    _material(spec, "scenery_wheel", rgba=(0.22, 0.22, 0.25, 1), specular=0.6, shininess=0.6)

    sleeper_top = -RAIL_HEIGHT_M
    _plane(spec, "ground", sleeper_top - 0.12, 60.0, "scenery_grass")
    _plane(spec, "ballast", sleeper_top - 0.04, 2.2, "scenery_ballast")
    _plane(spec, "sleepers", sleeper_top, SLEEPER_LENGTH_M / 2, "scenery_sleepers")
    half = TRACK_LENGTH_M / 2
    for k, y in enumerate(rail_y_m):
        spec.worldbody.add_geom(name=f"{SCENERY_PREFIX}rail{k}", type=mujoco.mjtGeom.mjGEOM_BOX,
                                pos=[TRACK_START_M + half, y, -RAIL_HEIGHT_M / 2],
                                size=[half, RAIL_HEAD_M / 2, RAIL_HEIGHT_M / 2], material="scenery_rail",
                                **_NO_CONTACT)
    for name in wheel_bodies:
        _dress_wheelset(spec, name, wheel_radius_m, rail_y_m, highlight=name == driven_body)

    # lights: a sun that follows the vehicle and casts shadows, a soft fill from the other side
    spec.worldbody.add_light(name="scenery_sun", mode=mujoco.mjtCamLight.mjCAMLIGHT_TRACKCOM,
                             type=mujoco.mjtLightType.mjLIGHT_DIRECTIONAL, pos=[-10, -12, 30],
                             dir=[0.35, 0.45, -1.0], diffuse=[0.75, 0.72, 0.65], specular=[0.3, 0.3, 0.3],
                             castshadow=True)
    spec.worldbody.add_light(name="scenery_fill", mode=mujoco.mjtCamLight.mjCAMLIGHT_TRACKCOM,
                             type=mujoco.mjtLightType.mjLIGHT_DIRECTIONAL, pos=[10, 15, 20],
                             dir=[-0.3, -0.6, -1.0], diffuse=[0.25, 0.27, 0.3], castshadow=False)
    vis = spec.visual
    vis.headlight.ambient = [0.35, 0.35, 0.38]
    vis.headlight.diffuse = [0.3, 0.3, 0.3]
    vis.headlight.specular = [0.05, 0.05, 0.05]
    vis.quality.shadowsize = 2048
    vis.map.haze = 0.25
    vis.rgba.haze = [0.85, 0.9, 0.97, 1.0]
    vis.global_.offwidth = max(vis.global_.offwidth, 1920)
    vis.global_.offheight = max(vis.global_.offheight, 1080)
    spec.stat.extent = vehicle_stat.extent
    spec.stat.center = vehicle_stat.center
