#!/usr/bin/env python3
"""OpenFOAM v1912 vs spillage on the turbulent half channel (issue 18, verification item 4).

  compare.py params CASE.toml
      prints the shell variables run.sh builds the OpenFOAM case from (all from the case file)
  compare.py compare CASE.toml FOAM_DIR SPILLAGE_DIR [--foam-wall S] [--spillage-wall S]
      reads both steady profiles and prints them side by side with the differences, U+ against
      the log law, C_f against Dean's correlation and the µs per cell-step of both codes.

Only the Python standard library and numpy.
"""
import sys

sys.dont_write_bytecode = True  # no __pycache__ in the repository
import tomllib


def load_case(path):
    with open(path, "rb") as f:
        case = tomllib.load(f)
    return case


def params(path):
    case = load_case(path)
    mesh = case["mesh"]
    assert mesh.get("generator") == "box", f"{path}: [mesh] generator must be 'box' for this comparison"
    assert mesh.get("periodic") == ["x"], f"{path}: [mesh] periodic must be ['x'] for this comparison"
    assert mesh.get("two_d", False), f"{path}: [mesh] two_d must be true for this comparison"
    num = case.get("numerics", {})
    turb = case["turbulence"]
    const = turb.get("constants", {})
    init = case["fluid"].get("initial", {})
    assert init.get("type", "uniform") == "uniform", f"{path}: [fluid.initial] type must be 'uniform'"
    assert num.get("time_scheme", "backward") == "euler", f"{path}: [numerics] time_scheme must be 'euler' (k, ε are always Euler in spillage)"
    scheme = num.get("convection", "linear")
    u_scheme = {"linear": "linear", "upwind": "upwind", "limited_linear": "limitedLinearV 1"}.get(scheme)
    assert u_scheme, f"{path}: [numerics] convection = {scheme!r} has no OpenFOAM twin here (linear, upwind, limited_linear)"
    dt = case["time"]["dt"]
    steps = case["time"]["steps"]
    u0 = init.get("velocity", [0.0, 0.0, 0.0])
    force = num.get("body_force", [0.0, 0.0, 0.0])
    (x0, y0, z0), (x1, y1, z1), (nx, ny, nz) = mesh["min"], mesh["max"], mesh["cells"]
    values = dict(
        x0=x0, y0=y0, z0=z0, x1=x1, y1=y1, z1=z1, nx=nx, ny=ny, nz=nz,
        dt=repr(dt), steps=steps, end_time=repr(dt * steps),
        nu=repr(case["fluid"]["kinematic_viscosity"]),
        u0x=u0[0], u0y=u0[1], u0z=u0[2], fx=force[0], fy=force[1], fz=force[2],
        k0=turb["initial_k"], eps0=turb["initial_epsilon"],
        a0=const.get("a0", 4.0), c2=const.get("c2", 1.9), sigma_k=const.get("sigma_k", 1.0),
        sigma_eps=const.get("sigma_epsilon", 1.2), c_mu=const.get("c_mu", 0.09),
        kappa=const.get("kappa", 0.41), wall_e=const.get("wall_e", 9.8),
        outer=num.get("max_outer_iterations", 3), piso=num.get("piso_correctors", 1),
        # spillage counts extra pressure solves per corrector, as nNonOrthogonalCorrectors does
        nonorth=num.get("non_orthogonal_correctors", 1),
        p_ini=num.get("p_initial_residual", 1e-8),
        relax_u=num.get("relax_velocity", 1.0), relax_p=num.get("relax_pressure", 1.0),
        u_scheme=f"'{u_scheme}'",
    )
    for key, value in values.items():
        print(f"{key}={value}")


if __name__ == "__main__":
    if len(sys.argv) >= 3 and sys.argv[1] == "params":
        params(sys.argv[2])
    elif len(sys.argv) >= 5 and sys.argv[1] == "compare":
        import compare_profiles
        sys.exit(compare_profiles.main(sys.argv[2:]))
    else:
        sys.exit(__doc__)
