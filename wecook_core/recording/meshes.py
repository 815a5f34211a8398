"""The arms as they look: each link's visual meshes from its URDF, as glTF binaries for Foxglove's 3D panel.

A URDF's ``<visual>`` elements give, per link, a mesh file (OBJ with its MTL materials, or STL), its origin in
the link frame and its scale. Each mesh is loaded with trimesh, split by material (so the Panda keeps its white
shells and dark joints), reduced with quadric decimation (fast-simplification) to about :data:`KEEP` of its
triangles (at least :data:`MIN_FACES` per part), and written as one GLB whose parts carry their material colour
(no textures), in glTF's Y-up axes (Foxglove turns glTF models to Z-up). A recording embeds these GLBs once,
in foxglove.ModelPrimitive ``data``.

Conversion takes about a second for the Panda; the GLBs are cached on disk
(``$XDG_CACHE_HOME/wecook/meshes``, keyed by the mesh file's content and the reduction) so later runs read them
in milliseconds. Visuals that are
boxes, cylinders or spheres come back as :class:`~wecook_core.execution.schedule.observer.Shape`.
"""

from __future__ import annotations

import functools
import hashlib
import math
import os
import xml.etree.ElementTree as ET
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from wecook_core.execution.schedule.observer import FrameInfo, Quat, Shape, Vec3

KEEP = 0.12
"""Share of a mesh part's triangles kept by decimation."""
MIN_FACES = 200
"""Parts with fewer triangles than this are kept whole."""
CACHE_VERSION = 2
Y_UP = ((1.0, 0.0, 0.0, 0.0), (0.0, 0.0, 1.0, 0.0), (0.0, -1.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0))
"""Z-up (URDF) to Y-up (glTF): Foxglove turns a glTF model +90 degrees about x to make it Z-up."""


@dataclass(frozen=True)
class LinkModel:
    """One visual mesh of a link: a GLB, where it sits in the link frame, its scale."""

    glb: bytes
    pose: tuple[Vec3, Quat]
    scale: Vec3
    color: tuple[float, float, float, float]
    """The URDF material's colour (the GLB has its own per-part colours)."""


@dataclass(frozen=True)
class LinkVisual:
    models: tuple[LinkModel, ...] = ()
    shapes: tuple[Shape, ...] = ()


def _floats(text: str | None, default: tuple[float, ...]) -> tuple[float, ...]:
    if not text:
        return default
    return tuple(float(v) for v in text.split())


def _rpy_quat(r: float, p: float, y: float) -> Quat:
    cr, sr, cp, sp, cy, sy = (math.cos(r / 2), math.sin(r / 2), math.cos(p / 2), math.sin(p / 2),
                              math.cos(y / 2), math.sin(y / 2))
    return (sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy, cr * cp * sy - sr * sp * cy,
            cr * cp * cy + sr * sp * sy)


def _mesh_file(urdf: Path, filename: str) -> Path:
    """``package://x/y.obj`` and relative names are resolved beside the URDF (as PyBullet does)."""
    name = filename.removeprefix("package://").removeprefix("file://")
    path = Path(name)
    if path.is_absolute():
        return path
    here = urdf.parent / path
    if here.is_file():
        return here
    parts = path.parts  # package://<package>/rest: try the rest beside the URDF
    return urdf.parent / Path(*parts[1:]) if len(parts) > 1 else here


def robot_visuals(urdf: str | Path) -> dict[str, LinkVisual]:
    """Link name -> its visuals (GLB models for meshes, shapes for primitives). A missing or unreadable mesh is
    left out (the link then has fewer parts); an unreadable URDF gives ``{}``."""
    return dict(_robot_visuals(str(Path(urdf).resolve())))


@functools.lru_cache(maxsize=8)
def _robot_visuals(urdf: str) -> tuple[tuple[str, LinkVisual], ...]:
    path = Path(urdf)
    try:
        root = ET.parse(path).getroot()
    except (OSError, ET.ParseError):
        return ()
    colors: dict[str, tuple[float, ...]] = {}
    for material in root.iter("material"):
        swatch = material.find("color")
        if material.get("name") and swatch is not None:
            colors[material.get("name", "")] = _floats(swatch.get("rgba"), (0.8, 0.8, 0.8, 1.0))
    out = []
    for link in root.findall("link"):
        models: list[LinkModel] = []
        shapes: list[Shape] = []
        for visual in link.findall("visual"):
            origin = visual.find("origin")
            xyz = _floats(origin.get("xyz") if origin is not None else None, (0.0, 0.0, 0.0))
            rpy = _floats(origin.get("rpy") if origin is not None else None, (0.0, 0.0, 0.0))
            pose = ((xyz[0], xyz[1], xyz[2]), _rpy_quat(*rpy[:3]))
            look = visual.find("material")
            rgba: tuple[float, ...] = (0.8, 0.8, 0.8, 1.0)
            if look is not None:
                inline = look.find("color")
                rgba = _floats(inline.get("rgba"), rgba) if inline is not None else colors.get(
                    look.get("name", ""), rgba)
            color: tuple[float, float, float, float] = (rgba[0], rgba[1], rgba[2], rgba[3])
            geometry = visual.find("geometry")
            if geometry is None:
                continue
            mesh, box = geometry.find("mesh"), geometry.find("box")
            cylinder, sphere = geometry.find("cylinder"), geometry.find("sphere")
            if mesh is not None and mesh.get("filename"):
                glb = mesh_glb(_mesh_file(path, mesh.get("filename", "")))
                if glb is not None:
                    s = _floats(mesh.get("scale"), (1.0, 1.0, 1.0))
                    models.append(LinkModel(glb, pose, (s[0], s[1], s[2]), color))
            elif box is not None:
                s = _floats(box.get("size"), (0.0, 0.0, 0.0))
                shapes.append(Shape("box", (s[0], s[1], s[2]), pose, color))
            elif cylinder is not None:
                d, h = 2 * float(cylinder.get("radius", 0)), float(cylinder.get("length", 0))
                shapes.append(Shape("cylinder", (d, d, h), pose, color))
            elif sphere is not None:
                d = 2 * float(sphere.get("radius", 0))
                shapes.append(Shape("sphere", (d, d, d), pose, color))
        out.append((link.get("name", ""), LinkVisual(tuple(models), tuple(shapes))))
    return tuple(out)


def _cache_dir() -> Path:
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "wecook" / "meshes"


@functools.lru_cache(maxsize=64)
def mesh_glb(path: Path) -> bytes | None:
    """The GLB of one mesh file (decimated, per-material colours), from the disk cache when it is there."""
    try:
        data = path.read_bytes()
    except OSError:
        return None
    key = hashlib.sha1(data + f"{path.suffix}|{KEEP}|{MIN_FACES}|{CACHE_VERSION}".encode()).hexdigest()
    cached = _cache_dir() / f"{key}.glb"
    try:
        return cached.read_bytes()
    except OSError:
        pass
    glb = convert_mesh(path)
    if glb is not None:
        try:
            cached.parent.mkdir(parents=True, exist_ok=True)
            tmp = cached.with_suffix(f".{os.getpid()}.tmp")
            tmp.write_bytes(glb)
            tmp.replace(cached)
        except OSError:  # a read-only home: convert again next time
            pass
    return glb


def convert_mesh(path: Path, keep: float = KEEP, min_faces: int = MIN_FACES) -> bytes | None:
    """Load ``path`` (OBJ/STL/DAE...), split by material, decimate each part, write a GLB (None if unreadable)."""
    import numpy as np
    import trimesh
    from trimesh.visual.material import PBRMaterial

    try:
        loaded: Any = trimesh.load(str(path), force="scene", group_material=True)
    except Exception:  # trimesh raises many kinds on a bad file
        return None
    scene = trimesh.Scene()
    for name, geometry in loaded.geometry.items():
        if not isinstance(geometry, trimesh.Trimesh) or len(geometry.faces) == 0:
            continue
        material = getattr(geometry.visual, "material", None)
        rgba = np.asarray(getattr(material, "main_color", (204, 204, 204, 255)), dtype=float)[:4] / 255.0
        mesh = trimesh.Trimesh(geometry.vertices, geometry.faces, process=True)
        if len(mesh.faces) >= min_faces:
            mesh = mesh.simplify_quadric_decimation(face_count=max(min_faces, int(len(mesh.faces) * keep)))
        mesh.apply_transform(np.asarray(Y_UP))
        mesh.visual = trimesh.visual.TextureVisuals(material=PBRMaterial(
            name=str(name), baseColorFactor=[float(c) for c in rgba], metallicFactor=0.1, roughnessFactor=0.6))
        scene.add_geometry(mesh, node_name=str(name), geom_name=str(name))
    if not scene.geometry:
        return None
    glb = scene.export(file_type="glb")
    return bytes(glb) if isinstance(glb, bytes | bytearray) else None


def glb_parts(glb: bytes) -> list[tuple[Any, Any, tuple[float, float, float, float]]]:
    """The parts of a GLB written by :func:`convert_mesh`, back in Z-up: (vertices n x 3, triangles m x 3,
    rgba 0..1)."""
    import io

    import numpy as np
    import trimesh

    scene: Any = trimesh.load(io.BytesIO(glb), file_type="glb", force="scene")
    back = np.linalg.inv(np.asarray(Y_UP))
    parts = []
    for name in scene.graph.nodes_geometry:
        transform, geometry_name = scene.graph[name]
        mesh = scene.geometry[geometry_name]
        vertices = trimesh.transform_points(mesh.vertices, back @ transform)
        material = getattr(mesh.visual, "material", None)
        factor = getattr(material, "baseColorFactor", None)
        rgba = np.asarray(factor if factor is not None else (204, 204, 204, 255), dtype=float) / 255.0
        parts.append((vertices, np.asarray(mesh.faces), (float(rgba[0]), float(rgba[1]), float(rgba[2]),
                                                          float(rgba[3]))))
    return parts


def arm_visuals(urdfs: Mapping[str, str | Path]) -> dict[str, LinkVisual]:
    """``"<pid>/<link>"`` -> visuals, for each arm's URDF (pid -> path)."""
    out: dict[str, LinkVisual] = {}
    for pid, urdf in urdfs.items():
        for link, visual in robot_visuals(urdf).items():
            out[f"{pid}/{link}"] = visual
    return out


def plan_arm_urdfs(plan_yaml: str) -> dict[str, str]:
    """pid -> URDF path of each agent of a plan's YAML (relative robots are in pybullet_data), ``{}`` if the
    YAML names none."""
    import yaml

    try:
        data = yaml.safe_load(plan_yaml)
    except yaml.YAMLError:
        return {}
    agents = data.get("agents") if isinstance(data, dict) else None
    out = {}
    for agent in agents if isinstance(agents, list) else ():
        if isinstance(agent, dict) and agent.get("pid") and agent.get("robot"):
            out[str(agent["pid"])] = _robot_path(str(agent["robot"]))
    return out


def _robot_path(urdf: str) -> str:
    path = Path(urdf)
    if path.is_absolute():
        return str(path)
    import pybullet_data

    return str(Path(pybullet_data.getDataPath()) / path)


def drawn_frames(frames: Sequence[FrameInfo], plan_yaml: str, *, meshes: bool = True,
                 ns: int = 0) -> tuple[tuple[FrameInfo, ...], dict[str, list[dict[str, Any]]]]:
    """Split a run's frames into what ``/scene`` draws (table, objects, links without meshes; a link's URDF
    primitives replace its bounding boxes) and ``/robot``'s model primitives per link frame."""
    from wecook_core.recording import foxglove

    visuals = arm_visuals(plan_arm_urdfs(plan_yaml)) if meshes else {}
    scene: list[FrameInfo] = []
    models: dict[str, list[dict[str, Any]]] = {}
    for frame in frames:
        visual = visuals.get(frame.frame_id)
        if visual is None or not (visual.models or visual.shapes):
            scene.append(frame)
            continue
        if visual.shapes:
            scene.append(FrameInfo(frame.frame_id, visual.shapes))
        if visual.models:
            models[frame.frame_id] = [foxglove.model_primitive(m.glb, m.pose, m.scale) for m in visual.models]
    return tuple(scene), models
