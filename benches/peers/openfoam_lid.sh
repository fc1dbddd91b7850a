#!/usr/bin/env bash
# Side by side with OpenFOAM v1912 (issue #6): the 2-D lid-driven cavity (Re = 100, n × n cells,
# Δt = 0.5/n) with the same settings in both codes: linear convection, backward (BDF2) time
# scheme, PIMPLE with 2 outer correctors, 2 PISO correctors, 1 non-orthogonal corrector, no
# relaxation, pressure tolerance 1e-7 (OpenFOAM: GAMG; fast: K-cycle AMG-preconditioned flexible CG), momentum 1e-7
# (OpenFOAM: symGaussSeidel smoothSolver; fast: Jacobi-BiCGStab), 1 core each.
# Prints both times per step, µs per cell-step and the ratio. Skips cleanly without OpenFOAM.
#
# usage: benches/peers/openfoam_lid.sh [n=256] [steps=20]
set -euo pipefail
n=${1:-256}
steps=${2:-20}
if ! command -v pimpleFoam >/dev/null 2>&1 || ! command -v blockMesh >/dev/null 2>&1; then
  echo "OpenFOAM (pimpleFoam, blockMesh) not found: skipping (apt-get install openfoam)"
  exit 0
fi
# Debian/Ubuntu's openfoam package needs its environment (WM_PROJECT_DIR for etc/controlDict)
for rc in /usr/share/openfoam/etc/bashrc /usr/lib/openfoam/openfoam1912/etc/bashrc /opt/openfoam1912/etc/bashrc; do
  if [ -z "${WM_PROJECT_DIR:-}" ] && [ -f "$rc" ]; then set +u; source "$rc" >/dev/null 2>&1 || true; set -u; fi
done
root=$(cd "$(dirname "$0")/../.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
dt=$(python3 -c "print(0.5/$n)")
end=$(python3 -c "print(($steps + 2) * 0.5/$n)")
mkdir -p "$work/case/system" "$work/case/constant" "$work/case/0"
header() { printf 'FoamFile { version 2.0; format ascii; class %s; object %s; }\n' "$1" "$2"; }
{ header dictionary blockMeshDict; cat <<EOT
convertToMeters 1;
vertices ((0 0 0) (1 0 0) (1 1 0) (0 1 0) (0 0 0.1) (1 0 0.1) (1 1 0.1) (0 1 0.1));
blocks (hex (0 1 2 3 4 5 6 7) ($n $n 1) simpleGrading (1 1 1));
boundary (
  lid { type wall; faces ((3 7 6 2)); }
  walls { type wall; faces ((0 4 7 3) (2 6 5 1) (1 5 4 0)); }
  frontAndBack { type empty; faces ((0 3 2 1) (4 5 6 7)); }
);
EOT
} > "$work/case/system/blockMeshDict"
{ header dictionary controlDict; cat <<EOT
application pimpleFoam; startFrom startTime; startTime 0; stopAt endTime; endTime $end;
deltaT $dt; writeControl timeStep; writeInterval 100000; purgeWrite 0; writeFormat binary;
runTimeModifiable false;
EOT
} > "$work/case/system/controlDict"
{ header dictionary fvSchemes; cat <<EOT
ddtSchemes { default backward; }
gradSchemes { default Gauss linear; }
divSchemes { default none; div(phi,U) Gauss linear; div((nuEff*dev2(T(grad(U))))) Gauss linear; }
laplacianSchemes { default Gauss linear corrected; }
interpolationSchemes { default linear; }
snGradSchemes { default corrected; }
EOT
} > "$work/case/system/fvSchemes"
{ header dictionary fvSolution; cat <<EOT
solvers {
  "p|pFinal" { solver GAMG; smoother GaussSeidel; tolerance 1e-7; relTol 0; }
  "U|UFinal" { solver smoothSolver; smoother symGaussSeidel; tolerance 1e-7; relTol 0; }
}
PIMPLE { nOuterCorrectors 2; nCorrectors 2; nNonOrthogonalCorrectors 1; momentumPredictor yes; pRefCell 0; pRefValue 0; }
relaxationFactors { equations { ".*" 1; } }
EOT
} > "$work/case/system/fvSolution"
{ header dictionary transportProperties; echo "transportModel Newtonian; nu 0.01;"; } > "$work/case/constant/transportProperties"
{ header dictionary turbulenceProperties; echo "simulationType laminar;"; } > "$work/case/constant/turbulenceProperties"
{ header volVectorField U; cat <<EOT
dimensions [0 1 -1 0 0 0 0]; internalField uniform (0 0 0);
boundaryField { lid { type fixedValue; value uniform (1 0 0); } walls { type noSlip; } frontAndBack { type empty; } }
EOT
} > "$work/case/0/U"
{ header volScalarField p; cat <<EOT
dimensions [0 2 -2 0 0 0 0]; internalField uniform 0;
boundaryField { lid { type zeroGradient; } walls { type zeroGradient; } frontAndBack { type empty; } }
EOT
} > "$work/case/0/p"
(cd "$work/case" && blockMesh > log.blockMesh 2>&1 && pimpleFoam > log.pimpleFoam 2>&1)
# ExecutionTime after each step; drop the first 2 steps (start-up), as the fast run does
foam=$(grep '^ExecutionTime' "$work/case/log.pimpleFoam" | awk '{print $3}' | awk -v s="$steps" '{t[NR]=$1} END {print (t[NR]-t[2])/(NR-2)}')
fast=$(cd "$root" && SPILLAGE_PEER_LID=$n SPILLAGE_PEER_STEPS=$steps cargo bench -q --bench fluid_step 2>/dev/null | awk '/fast_s_per_step/ {print $2}')
cells=$((n * n))
python3 - "$foam" "$fast" "$cells" <<'EOT'
import sys
foam, fast, cells = float(sys.argv[1]), float(sys.argv[2]), int(sys.argv[3])
print(f"lid-driven cavity {cells} cells, 1 core")
print(f"  pimpleFoam: {foam*1e3:9.3f} ms/step  {foam*1e6/cells:6.2f} µs/cell-step")
print(f"  fast:       {fast*1e3:9.3f} ms/step  {fast*1e6/cells:6.2f} µs/cell-step")
print(f"  pimpleFoam / fast = {foam/fast:.2f}")
EOT
