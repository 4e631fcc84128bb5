# Sourced by the bms-plate benchmarks: writes the calibrated rubber-sphere config to $config
# (set by the caller, as are $root and $work). The calibrated values are the ones the study's
# Makefile starts from (its START: bond modulus Ē, the sub-spheres' contact modulus, k̄s/k̄n),
# written the way `shapepress calibrate` writes calibrated.toml (a contact material for the
# sub-spheres, the bond in modulus form) into the shipped pipelines/configs/rubber-sphere.toml.
start=$(sed -nE 's/^START \?= *//p' "$root/pipelines/rubber-sphere/Makefile")
value() {  # name → its value in START
  tr ',' '\n' <<<"$start" | sed -nE "s/^$1=//p"
}
modulus=$(value modulus); contact_modulus=$(value contact_modulus); shear_ratio=$(value shear_ratio)
[[ -n "$modulus" && -n "$contact_modulus" && -n "$shear_ratio" ]] ||
  { echo "calibrated-config.sh: no modulus, contact_modulus, shear_ratio in the Makefile's START='$start'" >&2; exit 2; }

# [bond]: the modulus form replaces the k̄n, k̄s keys; [bms]: the sub-spheres' contact material.
sed -E -e '/^(normal|shear)_stiffness *=/d' \
       -e "s/^\[bond\]\$/[bond]\nmodulus = $modulus\nshear_ratio = $shear_ratio/" \
       -e 's/^\[bms\]$/[bms]\nmaterial = "rubber-contact"/' \
       "$root/pipelines/configs/rubber-sphere.toml" > "$config"
cat >> "$config" <<TOML

[[material]]
name = "rubber-contact"
youngs_modulus = $contact_modulus
poisson_ratio = 0.46
density = 2000

[[interaction]]
first = "rubber-contact"
second = "rubber-contact"
restitution = 0.7
sliding_friction = 0.5

[[interaction]]
first = "rubber-contact"
second = "wall"
restitution = 0.7
sliding_friction = 0.5

[[interaction]]
first = "rubber"
second = "rubber-contact"
restitution = 0.7
sliding_friction = 0.5
TOML

