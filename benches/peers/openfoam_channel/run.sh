#!/usr/bin/env bash
# Side by side with OpenFOAM v1912 (issue 18, verification item 4): the turbulent half channel
# cases/verification/turbulence/channel_395.toml (Re_tau = 395, realizable k–ε, standard wall
# functions) run by pimpleFoam and by spillage's reference solver with the same mesh, time step,
# number of steps, schemes and PIMPLE settings; compare.py prints both steady profiles side by
# side, max |ΔU_x|/U_b (criterion: < 2 %), the k, ε, ν_t differences, U⁺ against the log law,
# C_f against Dean's correlation and the µs per cell-step of both codes.
# Skips cleanly (exit 0) without OpenFOAM.
#
# usage: benches/peers/openfoam_channel/run.sh [WORKDIR]
#   WORKDIR keeps both runs (default: a temporary directory removed at exit).
#   SPILLAGE_CASE=path overrides the case file (same [mesh]/[turbulence] layout).
#   FOAM_RELAX_U=case relaxes OpenFOAM's momentum equation with the case's relax_velocity (the
#   default leaves it unrelaxed: see the fvSolution comment and README.md).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../../.." && pwd)
case_file=${SPILLAGE_CASE:-$root/cases/verification/turbulence/channel_395.toml}

if ! command -v pimpleFoam >/dev/null 2>&1 || ! command -v blockMesh >/dev/null 2>&1; then
  echo "OpenFOAM (pimpleFoam, blockMesh) not found: skipping the channel comparison (apt-get install openfoam)"
  exit 0
fi
if ! python3 -c 'import numpy, tomllib' >/dev/null 2>&1; then
  echo "python3 with numpy and tomllib (Python >= 3.11) not found: skipping the channel comparison"
  exit 0
fi
# Debian/Ubuntu's openfoam package needs its environment (WM_PROJECT_DIR for etc/controlDict)
for rc in /usr/share/openfoam/etc/bashrc /usr/lib/openfoam/openfoam1912/etc/bashrc /opt/openfoam1912/etc/bashrc; do
  if [ -z "${WM_PROJECT_DIR:-}" ] && [ -f "$rc" ]; then set +u; source "$rc" >/dev/null 2>&1 || true; set -u; fi
done

if [ $# -ge 1 ]; then
  work=$(mkdir -p "$1" && cd "$1" && pwd)
else
  work=$(mktemp -d)
  trap 'rm -rf "$work"' EXIT
fi
foam="$work/openfoam"
rm -rf "$foam"
mkdir -p "$foam/system" "$foam/constant" "$foam/0"

# every number of the OpenFOAM case comes from the spillage case file
eval "$(python3 "$here/compare.py" params "$case_file")"

header() { printf 'FoamFile { version 2.0; format ascii; class %s; object %s; }\n' "$1" "$2"; }

# Box (x0 y0 z0)–(x1 y1 z1), nx × ny × nz cells, uniform. Patches as spillage's box generator
# names them: x periodic (cyclic pair), y_min wall, y_max symmetry plane, z empty (two_d).
{ header dictionary blockMeshDict; cat <<EOT
scale 1;
vertices (
  ($x0 $y0 $z0) ($x1 $y0 $z0) ($x1 $y1 $z0) ($x0 $y1 $z0)
  ($x0 $y0 $z1) ($x1 $y0 $z1) ($x1 $y1 $z1) ($x0 $y1 $z1)
);
blocks (hex (0 1 2 3 4 5 6 7) ($nx $ny $nz) simpleGrading (1 1 1));
boundary (
  x_min { type cyclic; neighbourPatch x_max; faces ((0 4 7 3)); }
  x_max { type cyclic; neighbourPatch x_min; faces ((1 2 6 5)); }
  y_min { type wall; faces ((0 1 5 4)); }
  y_max { type symmetryPlane; faces ((3 7 6 2)); }
  z_ends { type empty; faces ((0 3 2 1) (4 5 6 7)); }
);
EOT
} > "$foam/system/blockMeshDict"

# ten writes, the last at the end (the last two tell whether the run is steady); ascii so that
# compare.py reads them without OpenFOAM tools
write_every=$(( steps >= 10 ? steps / 10 : 1 ))
{ header dictionary controlDict; cat <<EOT
application pimpleFoam; startFrom startTime; startTime 0; stopAt endTime; endTime $end_time;
deltaT $dt; writeControl timeStep; writeInterval $write_every; purgeWrite 0;
writeFormat ascii; writePrecision 17; writeCompression off; timeFormat general; timePrecision 10;
runTimeModifiable false;
EOT
} > "$foam/system/controlDict"

# spillage: Euler (time_scheme = "euler"); momentum convection $u_scheme; k, ε upwind and
# implicit Euler (reference/src/fluid/turbulence.rs); Gauss gradients with linear face values;
# orthogonal mesh, so "corrected" adds nothing.
{ header dictionary fvSchemes; cat <<EOT
ddtSchemes { default Euler; }
gradSchemes { default Gauss linear; }
divSchemes {
  default none;
  div(phi,U) Gauss $u_scheme;
  div(phi,k) bounded Gauss upwind;
  div(phi,epsilon) bounded Gauss upwind;
  div((nuEff*dev2(T(grad(U))))) Gauss linear;
}
laplacianSchemes { default Gauss linear corrected; }
interpolationSchemes { default linear; }
snGradSchemes { default corrected; }
wallDist { method meshWave; }
EOT
} > "$foam/system/fvSchemes"

# spillage factorises exactly: tight tolerances here. PIMPLE as [numerics]: outer iterations,
# PISO and non-orthogonal correctors, the outer stop on the initial p residual, implicit
# explicit relaxation of p in every outer iteration (the Final ones too); k and ε unrelaxed and
# solved once per step after the last outer iteration (turbOnFinalIterOnly, the default), as
# spillage does. Momentum: spillage relaxes a_P <- a_P/relax_velocity (Patankar); OpenFOAM's
# fvMatrix::relax first raises a_P to the sum of the off-diagonal magnitudes
# (D = max(|D|, sumOff)), which at this Courant number (~30, linear convection along x) is ~30x
# the time term, so with 3 outer iterations per step its pseudo-transient is ~10x slower
# (time constant ~110 s instead of ~12 s) and it is not steady at the end time. Neither
# relaxation changes the steady solution, so by default OpenFOAM's momentum is unrelaxed.
if [ "${FOAM_RELAX_U:-}" = case ]; then u_relax="\"U.*\" $relax_u;"; else u_relax=""; fi
{ header dictionary fvSolution; cat <<EOT
solvers {
  "p|pFinal" { solver PCG; preconditioner DIC; tolerance 1e-12; relTol 0; }
  "(U|k|epsilon)(|Final)" { solver PBiCGStab; preconditioner DILU; tolerance 1e-12; relTol 0; }
}
PIMPLE {
  nOuterCorrectors $outer; nCorrectors $piso; nNonOrthogonalCorrectors $nonorth;
  momentumPredictor yes; turbOnFinalIterOnly true; pRefCell 0; pRefValue 0;
  outerCorrectorResidualControl { p { tolerance $p_ini; relTol 0; } }
}
relaxationFactors {
  fields { "p.*" $relax_p; }
  equations { $u_relax }
}
EOT
} > "$foam/system/fvSolution"

# the body force as a specific (per unit volume, kinematic) explicit momentum source
{ header dictionary fvOptions; cat <<EOT
bodyForce {
  type vectorSemiImplicitSource; active yes;
  timeStart 0; duration 1e30; selectionMode all; volumeMode specific;
  injectionRateSuSp { U (($fx $fy $fz) 0); }
}
EOT
} > "$foam/constant/fvOptions"

{ header dictionary transportProperties; echo "transportModel Newtonian; nu $nu;"; } > "$foam/constant/transportProperties"
# constants: OpenFOAM's realizableKE defaults (A0 4, C2 1.9, σk 1, σε 1.2) and wall functions
# (Cmu 0.09, κ 0.41, E 9.8) are spillage's [turbulence.constants] defaults; written out so a
# case that changes them stays equivalent.
{ header dictionary turbulenceProperties; cat <<EOT
simulationType RAS;
RAS { RASModel realizableKE; turbulence on; printCoeffs on;
      realizableKECoeffs { A0 $a0; C2 $c2; sigmak $sigma_k; sigmaEps $sigma_eps; } }
EOT
} > "$foam/constant/turbulenceProperties"

wf="Cmu $c_mu; kappa $kappa; E $wall_e;"
{ header volVectorField U; cat <<EOT
dimensions [0 1 -1 0 0 0 0]; internalField uniform ($u0x $u0y $u0z);
boundaryField { x_min { type cyclic; } x_max { type cyclic; } y_min { type noSlip; }
  y_max { type symmetryPlane; } z_ends { type empty; } }
EOT
} > "$foam/0/U"
{ header volScalarField p; cat <<EOT
dimensions [0 2 -2 0 0 0 0]; internalField uniform 0;
boundaryField { x_min { type cyclic; } x_max { type cyclic; } y_min { type zeroGradient; }
  y_max { type symmetryPlane; } z_ends { type empty; } }
EOT
} > "$foam/0/p"
{ header volScalarField k; cat <<EOT
dimensions [0 2 -2 0 0 0 0]; internalField uniform $k0;
boundaryField { x_min { type cyclic; } x_max { type cyclic; } y_min { type kqRWallFunction; value uniform $k0; }
  y_max { type symmetryPlane; } z_ends { type empty; } }
EOT
} > "$foam/0/k"
{ header volScalarField epsilon; cat <<EOT
dimensions [0 2 -3 0 0 0 0]; internalField uniform $eps0;
boundaryField { x_min { type cyclic; } x_max { type cyclic; } y_min { type epsilonWallFunction; $wf value uniform $eps0; }
  y_max { type symmetryPlane; } z_ends { type empty; } }
EOT
} > "$foam/0/epsilon"
{ header volScalarField nut; cat <<EOT
dimensions [0 2 -1 0 0 0 0]; internalField uniform 0;
boundaryField { x_min { type cyclic; } x_max { type cyclic; } y_min { type nutkWallFunction; $wf value uniform 0; }
  y_max { type symmetryPlane; } z_ends { type empty; } }
EOT
} > "$foam/0/nut"

now() { python3 -c 'import time; print(time.time())'; }
echo "OpenFOAM $WM_PROJECT_VERSION: blockMesh + pimpleFoam ($steps steps of $dt s, $nx x $ny x $nz cells) in $foam"
(cd "$foam" && blockMesh > log.blockMesh 2>&1)
t0=$(now)
(cd "$foam" && pimpleFoam > log.pimpleFoam 2>&1) || { echo "pimpleFoam failed: tail of $foam/log.pimpleFoam:"; tail -20 "$foam/log.pimpleFoam"; exit 1; }
t1=$(now)
(cd "$foam" && postProcess -func writeCellCentres -latestTime > log.cellCentres 2>&1) || true

out="$work/spillage"
echo "spillage: reference solver on $case_file in $out"
(cd "$root" && cargo build --release -q)
bin="${CARGO_TARGET_DIR:-$root/target}/release/spillage"
case "$bin" in /*) ;; *) bin="$root/$bin" ;; esac
t2=$(now)
(cd "$root" && "$bin" run "$case_file" --solver reference --threads 1 --out "$out" --force > "$work/log.spillage" 2>&1) \
  || { echo "spillage failed: tail of $work/log.spillage:"; tail -20 "$work/log.spillage"; exit 1; }
t3=$(now)

python3 "$here/compare.py" compare "$case_file" "$foam" "$out" \
  --foam-wall "$(python3 -c "print($t1 - $t0)")" --spillage-wall "$(python3 -c "print($t3 - $t2)")"
