# Peak punch stress of the spherical Avicel run against β (at λp = 0.3) and λp (at β = 1.3),
# from sweep.csv (Makefile beside this script). Writes peak_stress_beta.svg/png and
# peak_stress_lambda.svg/png in the current folder.
set datafile separator ','
set datafile commentschars '#'
set datafile columnheaders
set key off
set grid
set ylabel 'peak punch stress [MPa]'
set yrange [0:*]
do for [kind in 'beta lambda'] {
  if (kind eq 'beta') {
    set xlabel 'multi-contact prefactor beta (lambda_p = 0.3)'
    set title 'Spherical Avicel PH 200: peak stress against beta'
  } else {
    set xlabel 'plasticity ratio lambda_p (beta = 1.3)'
    set title 'Spherical Avicel PH 200: peak stress against lambda_p'
  }
  do for [format in 'svg png'] {
    if (format eq 'svg') { set terminal svg size 640,420 font 'sans,12' } else { set terminal pngcairo size 960,630 font 'sans,14' }
    set output sprintf('peak_stress_%s.%s', kind, format)
    plot data using (kind eq 'beta' ? (abs($2 - 0.3) < 1e-9 ? $1 : 1/0) : (abs($1 - 1.3) < 1e-9 ? $2 : 1/0)):3 with linespoints pt 7 lw 2
    unset output
  }
}
