# Grinding fit: measured against fitted, written by chatter 0.1.0.
# Reproduce or restyle: cd into this directory, edit, then run
#   gnuplot grinding_underwater_seed000_fit.gp
# It reads grinding_underwater_seed000_fit.dat and writes grinding_underwater_seed000_fit.png.

fs = 14
set terminal pngcairo size 1200,800 enhanced font 'DejaVu Sans,'.fs linewidth 1.2
set output 'grinding_underwater_seed000_fit.png'
set encoding utf8
set datafile missing '?'
data = 'grinding_underwater_seed000_fit.dat'
set border lw 1 lc rgb '#404040'
set grid back lw 1 lc rgb '#d0d0d0'
set multiplot layout 1,3 title 'Grinding fit (poly11): underwater_tests_seed000.csv' noenhanced
set key top left
set size ratio -1
set title 'removal: R^2 = 0.9513' noenhanced
set xlabel 'measured (mm^3/s)'
set ylabel 'fitted (mm^3/s)'
set xrange [27.827701:99.770109]
set yrange [27.827701:99.770109]
plot x with lines dt 2 lc rgb '#808080' title 'measured = fitted', \
  data index 0 using 1:2 with points pt 7 ps 1.3 lc rgb '#1f77b4' title 'tests'
set title 'wear: R^2 = 0.5636' noenhanced
set xlabel 'measured (mm^3/s)'
set ylabel 'fitted (mm^3/s)'
set xrange [-40.488708:347.95661]
set yrange [-40.488708:347.95661]
plot x with lines dt 2 lc rgb '#808080' title 'measured = fitted', \
  data index 1 using 1:2 with points pt 7 ps 1.3 lc rgb '#d62728' title 'tests'
set title 'normal_force: R^2 = 0.9819' noenhanced
set xlabel 'measured (N)'
set ylabel 'fitted (N)'
set xrange [144.02:310.78]
set yrange [144.02:310.78]
plot x with lines dt 2 lc rgb '#808080' title 'measured = fitted', \
  data index 2 using 1:2 with points pt 7 ps 1.3 lc rgb '#2ca02c' title 'tests'
unset multiplot
