"""Fuzz cases of the public API outside the multibody engine (run in the child of
fuzz_harness.py): materials, laminates, plates, shell models, contact laws, friction, the impact,
scene files and result files. Each takes JSON arguments and returns the values whose finiteness is
checked."""
from __future__ import annotations

import functools
import re
import tempfile
from pathlib import Path

import numpy as np

import deployfx as dfx
from deployfx import contact
from fuzz_harness import case

_TMP = Path(tempfile.mkdtemp(prefix="deployfx-fuzz-"))
MATERIAL_NAMES = ("E", "nu", "rho", "E1", "E2", "G12", "G13", "G23", "nu12")
LAMINATE_NAMES = ("thickness", "angle_deg", "plies", "material") + MATERIAL_NAMES


def _material(spec):
    if not isinstance(spec, dict):
        return spec  # a wrong type on purpose
    kind, args = spec.get("type"), {k: v for k, v in spec.items() if k != "type"}
    return dfx.Isotropic(**args) if kind == "isotropic" else dfx.Orthotropic(**args)


def _laminate(plies):
    if not isinstance(plies, list):
        return dfx.Laminate(plies)
    return dfx.Laminate([dfx.Ply(_material(p["material"]), p["thickness"], p["angle_deg"])
                         if isinstance(p, dict) else p for p in plies])


@case("isotropic", MATERIAL_NAMES)
def isotropic(E, nu, rho):
    m = dfx.Isotropic(E, nu, rho)
    return m.G, m._impl.Q()


@case("orthotropic", MATERIAL_NAMES)
def orthotropic(E1, E2, G12, G13, G23, nu12, rho):
    m = dfx.Orthotropic(E1=E1, E2=E2, G12=G12, G13=G13, G23=G23, nu12=nu12, rho=rho)
    return m.nu21, m._impl.Q(), m._impl.Q_bar(0.3), m._impl.Qs_bar(0.3)


@case("ply", LAMINATE_NAMES)
def ply(material, thickness, angle_deg):
    p = dfx.Ply(_material(material), thickness, angle_deg)
    return p.Q_bar()


@case("laminate", LAMINATE_NAMES)
def laminate(plies):
    lam = _laminate(plies)
    return (lam.A, lam.B, lam.D, lam.As, lam.thickness, lam.mass_per_area,
            lam.first_moment_per_area, lam.rotary_inertia_per_area, lam.z)


@case("plate", LAMINATE_NAMES + ("length", "width", "nx", "ny", "n", "boundary", "pressure",
                                 "quads", "Plate"))
def plate(length, width, nx, ny, plies, method, n, boundary, pressure):
    p = dfx.Plate(length, width, _laminate(plies), nx, ny)
    if method == "frequencies":
        return p.natural_frequencies(n, boundary)
    if method == "modes":
        return p.modes(n, boundary)
    if method == "static":
        return p.static(pressure, boundary)
    if method == "fixed_dofs":
        return p.fixed_dofs(boundary)
    return p.mass, p.x, p.y, p.model.stiffness_matrix(), p.model.mass_matrix()


def _grid(length, width, nx, ny):
    x, y = np.meshgrid(np.linspace(0, length, nx + 1), np.linspace(0, width, ny + 1))
    nodes = np.column_stack([x.ravel(), y.ravel(), np.zeros(x.size)])
    quads = [[j * (nx + 1) + i, j * (nx + 1) + i + 1, (j + 1) * (nx + 1) + i + 1,
              (j + 1) * (nx + 1) + i] for j in range(ny) for i in range(nx)]
    return nodes, quads


@case("shell", LAMINATE_NAMES + ("nodes", "quads", "ref_axis", "pressure", "load", "u", "N", "n",
                                 "fixed_dofs", "ShellModel"))
def shell(length, width, nx, ny, node_edit, quad_edit, ref_axis, plies, method, scale, n, fixed):
    nodes, quads = _grid(length, width, nx, ny)
    nodes = nodes.tolist()
    if node_edit is not None:
        k, axis, value = node_edit
        nodes[k % len(nodes)][axis % 3] = value
    if quad_edit is not None:
        e, a, value = quad_edit
        quads[e % len(quads)][a % 4] = value
    m = dfx.ShellModel(nodes, quads, _laminate(plies), ref_axis)
    ndof = m.num_dofs
    pattern = np.sin(np.arange(ndof) * 0.7)  # a deterministic, non-trivial displacement shape
    if not isinstance(scale, (int, float)) or isinstance(scale, bool):
        # A wrong type goes to the API as it is: the pressure, or the displacements u.
        return m.pressure_load(scale) if method == "pressure_load" else m.internal_force(scale)
    if method == "pressure_load":
        return m.pressure_load(scale)
    if method == "static":
        return m.static(scale * pattern, fixed)
    if method == "internal_force":
        return m.internal_force(scale * pattern)
    if method == "strain_energy":
        return m.strain_energy(scale * pattern)
    if method == "geometric_stiffness":
        return m.geometric_stiffness((scale, -0.5 * scale, 0.25 * scale))
    if method == "geometric_stiffness_from":
        return m.geometric_stiffness_from(scale * pattern)
    if method == "modes":
        return m.modes(n, fixed)
    if method == "inertia":
        fi = m.floating_frame_inertia()
        return fi.mass, fi.J0, fi.inertia_tensor(scale * pattern)
    return m.mass, m.stiffness_matrix(), m.mass_matrix()


CONTACT_NAMES = ("kind", "K", "n", "D", "e", "delta", "delta_dot", "v0", "mass", "dt", "impact",
                 "contact", "mu", "v_reg", "v_t", "F_n", "friction")


@case("contact_force", CONTACT_NAMES)
def contact_force(kind, K, n, D, e, delta, delta_dot, v0):
    law = contact.ContactLaw(kind, K=K, n=n, D=D, e=e)
    return law.hysteresis_factor, law.force(delta, delta_dot, v0)


@case("friction_force", CONTACT_NAMES)
def friction_force(mu, v_reg, v_t, F_n):
    return contact.Friction(mu, v_reg).force(v_t, F_n)


@case("impact", CONTACT_NAMES + ("mass_kg", "v0_m_s", "dt_s"))
def impact(kind, K, n, D, e, mass_kg, v0_m_s, dt_s, record):
    law = contact.ContactLaw(kind, K=K, n=n, D=D, e=e)
    r = contact.impact(law, mass_kg, v0_m_s, dt_s=dt_s, record=record)
    return r, contact.impact_time_scale(law, mass_kg, v0_m_s)


# ------------------------------------------------------------------------------------------------
# Files: mutations of a saved scene or result

def mutate(data, ops):
    """Apply ``ops`` (JSON lists) to ``data`` (str or bytes); positions are fractions of the
    current length, so that the same ops apply to any file."""
    text = isinstance(data, str)
    for op in ops:
        name, frac = op[0], op[1]
        pos = int(frac * len(data)) if data else 0
        if name == "truncate":
            data = data[:pos]
        elif name == "insert":
            data = data[:pos] + (op[2] if text else op[2].encode("utf-8", "replace")) + data[pos:]
        elif name == "delete":
            data = data[:pos] + data[pos + op[2]:]
        elif name == "flip" and not text:
            if pos < len(data):
                data = data[:pos] + bytes([data[pos] ^ (op[2] & 0xFF or 1)]) + data[pos + 1:]
        elif name == "lines" and text:
            lines = data.splitlines(keepends=True)
            if lines:
                k = int(frac * len(lines)) % len(lines)
                action = op[2]
                if action == "drop":
                    del lines[k]
                elif action == "dup":
                    lines.insert(k, lines[k])
                elif action == "swap" and k + 1 < len(lines):
                    lines[k], lines[k + 1] = lines[k + 1], lines[k]
            data = "".join(lines)
        elif name == "number" and text:
            # Replace the k-th number in the text by op[2] (a string: "nan", "1e400", "-0", ...).
            matches = list(re.finditer(r"-?\d+(\.\d+)?([eE][-+]?\d+)?", data))
            if matches:
                m = matches[int(frac * len(matches)) % len(matches)]
                data = data[:m.start()] + op[2] + data[m.end():]
    return data


@functools.lru_cache(maxsize=None)
def _scene_text(suffix):
    scene = (dfx.Scene().set_base(100.0, 10.0)
             .set_hinge(point=(0.1, 0.0, 0.0), axis=(0.0, 1.0, 0.0), tau0=1.0, k_theta=0.5)
             .add_rigid_part(1.0, np.eye(3), (0.05, 0.0, 0.0)))
    plate = dfx.Plate(0.5, 0.3, dfx.Laminate([dfx.Ply(dfx.Isotropic(70e9, 0.3, 2700.0), 2e-3)]),
                      2, 1)
    scene.set_appendage(plate.model, plate.fixed_dofs("CFFF"), fidelity="linear")
    scene.set_lock(np.pi / 2, 0.03, 0.2e-3, contact.ContactLaw("paper", K=1e9, n=1.5, D=1e3),
                   friction=contact.Friction(0.25))
    path = _TMP / f"base{suffix}"
    dfx.save_scene(scene, path)
    return path.read_text(encoding="utf-8")


SCENE_NAMES = ("fuzzscene", "scene file", "hinges", "base", "parts", "schema", "version")


@case("scene_file", SCENE_NAMES)
def scene_file(suffix, ops, keep_check):
    text = _scene_text(suffix)
    if not keep_check:
        text = "".join(l for l in text.splitlines(keepends=True) if "content_sha256" not in l)
    path = _TMP / f"fuzzscene{suffix}"
    path.write_text(mutate(text, ops), encoding="utf-8", errors="surrogatepass")
    scene = dfx.load_scene(path)
    return dfx.scene_file.scene_to_dict(scene)


@functools.lru_cache(maxsize=None)
def _result_bytes():
    t = np.linspace(0.0, 1.0, 40)
    r = dfx.Result({"t": t, "x": np.sin(t), "v": np.outer(t, [1.0, 2.0, 3.0])},
                   units={"x": "m"}, metadata={"model": "linear", "dt": 0.025})
    path = _TMP / "base.npz"
    r.save(path)
    return path.read_bytes()


@case("result_file", ("fuzzresult",))
def result_file(ops):
    path = _TMP / "fuzzresult.npz"
    path.write_bytes(mutate(_result_bytes(), ops))
    r = dfx.load(path)
    return {name: r[name] for name in r.series}, r.metadata
