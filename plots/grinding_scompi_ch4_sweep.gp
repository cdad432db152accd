# Grinding: removal, depth and force against power, written by chatter 0.1.0.
# Reproduce or restyle: cd into this directory, edit, then run
#   gnuplot grinding_scompi_ch4_sweep.gp
# It reads grinding_scompi_ch4_sweep.dat and writes grinding_scompi_ch4_sweep.png.

fs = 14
set terminal pngcairo size 1200,800 enhanced font 'DejaVu Sans,'.fs linewidth 1.2
set output 'grinding_scompi_ch4_sweep.png'
set encoding utf8
set datafile missing '?'
data = 'grinding_scompi_ch4_sweep.dat'
set border lw 1 lc rgb '#404040'
set grid back lw 1 lc rgb '#d0d0d0'
set multiplot layout 3,1 title 'grinding_scompi_ch4: grinding against power' noenhanced
set xrange [250:2500]
set key top left
set lmargin 12
set object 1 rect from 500, graph 0 to 2000, graph 1 back fc rgb '#9ecae1' fs solid 0.25 noborder
set ylabel 'removal rate (mm^3/s)'
unset xlabel
plot data index 0 using 1:2 with lines lw 2 lc rgb '#1f77b4' title '40 mm/s', \
  data index 1 using 1:2 with lines lw 2 lc rgb '#d62728' title '60 mm/s', \
  data index 2 using 1:2 with lines lw 2 lc rgb '#2ca02c' title '80 mm/s'
set ylabel 'maximum depth h_0 (mm)'
unset xlabel
plot data index 0 using 1:3 with lines lw 2 lc rgb '#1f77b4' title '40 mm/s', \
  data index 1 using 1:3 with lines lw 2 lc rgb '#d62728' title '60 mm/s', \
  data index 2 using 1:3 with lines lw 2 lc rgb '#2ca02c' title '80 mm/s'
set ylabel 'normal force (N)'
set xlabel 'useful grinding power (W)   [blue: powers of the impacts table]'
plot data index 0 using 1:4 with lines lw 2 lc rgb '#1f77b4' title '40 mm/s', \
  data index 1 using 1:4 with lines lw 2 lc rgb '#d62728' title '60 mm/s', \
  data index 2 using 1:4 with lines lw 2 lc rgb '#2ca02c' title '80 mm/s'
unset multiplot
