# Sourced by run.sh and instructions.sh: checks the tools and the binary, then makes a scratch
# folder holding the reference scene for every engine (packing.txt for shapepress, packing.data,
# liggghts.in and punch.stl for LIGGGHTS, packing.data and lammps.in for LAMMPS) and enters it. Expects: script (the caller's name for
# messages), here (this folder), root (the repository), and the tools to check as arguments.
shapepress=${SHAPEPRESS:-$root/build/app/shapepress}
for tool in "$@"; do
  command -v "$tool" >/dev/null || { echo "$script: $tool is missing: scripts/install-deps.sh --peers" >&2; exit 2; }
done
[[ -x "$shapepress" ]] || { echo "$script: $shapepress is not built: scripts/build.sh" >&2; exit 2; }
work=$(mktemp -d -t "shapepress-$script.XXXXXX")
trap 'rm -rf "$work"' EXIT
cd "$work"
python3 "$here/gen_packing.py" >/dev/null
cp "$here/liggghts.in" "$here/punch.stl" "$here/lammps.in" .
particles=20000
