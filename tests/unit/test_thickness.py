"""The thinnest part of a closed mesh (contact/thickness.py), which sets the guard lattice's spacing.

References are the shapes' own geometry, exact for the faceted meshes trimesh makes:
- a k-section cylinder of radius r: the distance between opposite flats, 2 r cos(pi / k) for even k;
- a box: its smallest edge; a sphere (icosphere): the diameter within the faceting, 2 r cos of the largest
  angle a face's centre makes with its vertices from the centre (>= 0.99 x 2 r at 3 subdivisions);
- a torus: the tube's diameter 2 r within 10 % (the issue's tolerance; faceting makes it 1 % short);
- a thin spherical shell (outer radius 1 m, inner 0.95 m, inner surface inverted): its 0.05 m wall.
Before this module, a trimesh cylinder gave about 3e-10 m (each ray hit its own face) and the guard lattice
sized from it exhausted the machine's memory.
"""

import math

import numpy as np
import pytest
import trimesh

from geompm.contact.thickness import face_chords, thinnest_part


def _thin(mesh):
    return thinnest_part(mesh.vertices, mesh.faces, mesh.face_normals)


@pytest.mark.parametrize("sections", [8, 16, 32, 64, 128])
def test_cylinder_is_its_diameter(sections):
    """trimesh's cylinder (r = 0.1 m, 0.6 m long) at 8 to 128 sections: the flats' distance 2 r cos(pi/k)."""
    cyl = trimesh.creation.cylinder(radius=0.1, height=0.6, sections=sections)
    assert _thin(cyl) == pytest.approx(0.2 * math.cos(math.pi / sections), rel=1e-9)


@pytest.mark.parametrize("make", [lambda m: m.subdivide().subdivide(), lambda m: m.convex_hull],
                         ids=["subdivided", "convex_hull"])
def test_cylinder_variants(make):
    """The subdivided cylinder (2 048 faces) and its convex hull keep the 32-section flats' distance."""
    cyl = make(trimesh.creation.cylinder(radius=0.1, height=0.6))
    assert _thin(cyl) == pytest.approx(0.2 * math.cos(math.pi / 32), rel=1e-9)


def test_box_sphere_capsule():
    """Box 1 x 0.1 x 2 m: 0.1 m exactly; icosphere r = 0.5 m: within 1 % of 1 m; capsule r = 0.2 m: within
    1 % of its 0.4 m diameter (the hemispherical ends do not make it thinner)."""
    assert _thin(trimesh.creation.box([1.0, 0.1, 2.0])) == pytest.approx(0.1, rel=1e-12)
    assert _thin(trimesh.creation.icosphere(3, radius=0.5)) == pytest.approx(1.0, rel=0.01)
    assert _thin(trimesh.creation.capsule(height=1.0, radius=0.2)) == pytest.approx(0.4, rel=0.01)


def test_torus_and_thin_shell():
    """Torus (R = 1 m, tube r = 0.1 m): the tube's 0.2 m within 10 %; a shell 0.05 m thick: within 1 %."""
    assert _thin(trimesh.creation.torus(1.0, 0.1)) == pytest.approx(0.2, rel=0.10)
    outer = trimesh.creation.icosphere(4, radius=1.0)
    inner = trimesh.creation.icosphere(4, radius=0.95)
    inner.invert()
    shell = trimesh.util.concatenate([outer, inner])
    assert _thin(shell) == pytest.approx(0.05, rel=0.01)


def test_scale_and_large_meshes():
    """A chord scales with the mesh (1e-6 to 1e6: relative error below 1e-6), and a 327 680-face sphere
    is measured (its diameter within 0.1 %) without the memory trimesh's own ray query needed."""
    box = trimesh.creation.box([1.0, 0.3, 2.0])
    for s in (1e-6, 1e-3, 1.0, 1e3, 1e6):
        assert thinnest_part(box.vertices * s, box.faces) == pytest.approx(0.3 * s, rel=1e-6)
    big = trimesh.creation.icosphere(7, radius=1.0)
    assert _thin(big) == pytest.approx(2.0, rel=1e-3)


def test_degenerate_and_open_meshes():
    """A zero-area face is neither a ray's origin nor its end; an open mesh (a lone triangle) has no chord."""
    box = trimesh.creation.box([1.0, 0.2, 1.0])
    faces = np.vstack([box.faces, [[0, 0, 1]]])
    chords = face_chords(box.vertices, faces)
    assert np.isinf(chords[-1])
    assert np.nanmin(chords) == pytest.approx(0.2, rel=1e-9)
    assert thinnest_part(np.eye(3), np.array([[0, 1, 2]])) is None
