"""How cameras see a world: Gazebo classic's lighting in MuJoCo's renderer.

Gazebo (OGRE, fixed-function Phong) lights a surface with the scene's ambient light times the
material's ambient colour, plus, for each light, its diffuse colour times the material's
diffuse colour times ``max(0, n·l)`` (Lambert), plus a specular term; there is no headlight,
and the sky is the scene's background colour. MuJoCo's classic renderer computes the same sum,
with one difference: a material reflects ambient and diffuse light with one colour (its
``rgba``). So:

- MuJoCo's headlight is off; the scene's ambient light is one more light that has only an
  ambient colour (MuJoCo's global ambient is zero); world lights have no ambient colour.
- A material's ``rgba`` is its diffuse colour; where its ambient colour differs, the
  difference under the scene's ambient light goes into MuJoCo's (scalar, possibly negative)
  emission, exact for grey ambient light and ambient colours proportional to diffuse ones.
- The background is a flat skybox of the scene's background colour (unlit, exact).
- Directional, point and spot lights keep their direction, diffuse and specular colours and
  attenuation (constant, linear, quadratic; MuJoCo has no range cut-off); a spot's outer
  angle is OpenGL's cut-off, its falloff the spot exponent; a point light is a spot
  without cut-off. OpenGL's fixed pipeline has eight
  lights: the ambient one and the first seven of the world (a warning names the rest).
"""

from __future__ import annotations

import logging
import math
from typing import Final

import mujoco
import numpy as np

from belvedere.description.urdf import transform
from belvedere.world import Light, Material, Scene, WorldModel

__all__ = ["MAX_WORLD_LIGHTS", "add_scene", "apply_material"]

logger = logging.getLogger("belvedere.physics")

MAX_WORLD_LIGHTS: Final = 7
"""OpenGL's eight fixed-function lights, less the scene's ambient light."""
_AMBIENT_LIGHT: Final = "belvedere/scene_ambient"
_BACKGROUND: Final = "belvedere/background"


def add_scene(spec: mujoco.MjSpec, world: WorldModel) -> None:
    """The world's ``<scene>`` and lights, as cameras will render them."""
    scene = world.scene
    headlight = spec.visual.headlight
    headlight.active = 0
    headlight.ambient = [0.0, 0.0, 0.0]
    headlight.diffuse = [0.0, 0.0, 0.0]
    headlight.specular = [0.0, 0.0, 0.0]
    ambient = spec.worldbody.add_light(name=_AMBIENT_LIGHT)
    ambient.type = mujoco.mjtLightType.mjLIGHT_DIRECTIONAL
    ambient.dir = [0.0, 0.0, -1.0]
    ambient.ambient = [float(c) for c in scene.ambient[:3]]
    ambient.diffuse = [0.0, 0.0, 0.0]
    ambient.specular = [0.0, 0.0, 0.0]
    ambient.castshadow = False
    background = [float(c) for c in scene.background[:3]]
    spec.add_texture(
        name=_BACKGROUND,
        type=mujoco.mjtTexture.mjTEXTURE_SKYBOX,
        builtin=mujoco.mjtBuiltin.mjBUILTIN_FLAT,
        rgb1=background,
        rgb2=background,
        width=4,
        height=4,
    )
    lights = [light for light in world.lights if light.type in ("directional", "point", "spot")]
    for light in world.lights:
        if light not in lights:
            logger.warning(
                "%s: warning: light %r has type %r (directional, point or spot); not rendered",
                light.source or world.path or "<world>",
                light.name,
                light.type,
            )
    for light in lights[MAX_WORLD_LIGHTS:]:
        logger.warning(
            "%s: warning: light %r is not rendered: cameras render the first %d lights of "
            "a world (OpenGL's fixed-function limit)",
            light.source or world.path or "<world>",
            light.name,
            MAX_WORLD_LIGHTS,
        )
    for i, light in enumerate(lights[:MAX_WORLD_LIGHTS]):
        _add_light(spec, light, i, shadows=scene.shadows)


def _add_light(spec: mujoco.MjSpec, light: Light, index: int, *, shadows: bool) -> None:
    pose = transform(light.pose)
    direction = pose[:3, :3] @ np.asarray(light.direction, dtype=float)
    norm = float(np.linalg.norm(direction))
    direction = direction / norm if norm > 0 else np.array([0.0, 0.0, -1.0])
    mj = spec.worldbody.add_light(name=f"belvedere/light_{index}/{light.name}")
    mj.pos = [float(v) for v in pose[:3, 3]]
    mj.dir = [float(v) for v in direction]
    mj.ambient = [0.0, 0.0, 0.0]
    mj.diffuse = [float(c) for c in light.diffuse[:3]]
    mj.specular = [float(c) for c in light.specular[:3]]
    mj.castshadow = bool(shadows and light.cast_shadows)
    if light.type == "directional":
        mj.type = mujoco.mjtLightType.mjLIGHT_DIRECTIONAL
        return
    fall = light.attenuation
    mj.attenuation = [fall.constant, fall.linear, fall.quadratic]
    if light.type == "spot":
        mj.type = mujoco.mjtLightType.mjLIGHT_SPOT
        outer = light.spot_outer_angle if light.spot_outer_angle > 0 else math.pi / 2
        mj.cutoff = min(90.0, math.degrees(outer / 2))
        mj.exponent = max(0.0, min(128.0, light.spot_falloff))
    else:  # OpenGL's point light: a spot without cut-off (MuJoCo's point type is not)
        mj.type = mujoco.mjtLightType.mjLIGHT_SPOT
        mj.cutoff = 180.0
        mj.exponent = 0.0


def apply_material(
    spec: mujoco.MjSpec, geom: mujoco.MjsGeom, material: Material, *, scene: Scene | None = None
) -> None:
    """Give a visual geom ``material``'s Phong colours (see the module's notes)."""
    ambient_light = np.asarray((scene or Scene()).ambient[:3], dtype=float)
    diffuse = np.asarray(material.diffuse[:3], dtype=float)
    ambient = np.asarray(material.ambient[:3], dtype=float)
    emissive = np.asarray(material.emissive[:3], dtype=float)
    extra = float(np.mean((ambient - diffuse) * ambient_light + emissive))
    brightness = float(np.mean(diffuse))
    emission = extra / brightness if brightness > 1e-6 else 0.0
    rgba = [*(float(c) for c in diffuse), float(material.diffuse[3])]
    mj = spec.add_material(name=f"{geom.name}/material")
    mj.rgba = rgba
    mj.emission = emission
    mj.specular = float(np.clip(np.mean(material.specular[:3]), 0.0, 1.0))
    mj.shininess = float(np.clip(material.shininess / 128.0, 0.0, 1.0))
    mj.reflectance = 0.0
    geom.material = mj.name
    geom.rgba = rgba
