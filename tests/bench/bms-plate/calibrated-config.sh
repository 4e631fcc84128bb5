# Sourced by the bms-plate benchmarks: writes the calibrated rubber-sphere config to $config
# (set by the caller, as are $root and $work). The shipped pipelines/configs/rubber-sphere.toml
# carries the N = 545 calibration (bond modulus Ē, k̄s/k̄n, the sub-spheres' contact material)
# and the quasi-static loading; the benchmarks press one fill (the config's [bms] fills).
cp "$root/pipelines/configs/rubber-sphere.toml" "$config"
