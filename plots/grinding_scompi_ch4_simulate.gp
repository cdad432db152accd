# Grinding simulation, written by chatter 0.1.0.
# Reproduce or restyle: cd into this directory, edit, then run
#   gnuplot grinding_scompi_ch4_simulate.gp
# It reads grinding_scompi_ch4_simulate.dat and writes grinding_scompi_ch4_simulate.png.

fs = 14
set terminal pngcairo size 1200,800 enhanced font 'DejaVu Sans,'.fs linewidth 1.2
set output 'grinding_scompi_ch4_simulate.png'
set encoding utf8
set datafile missing '?'
data = 'grinding_scompi_ch4_simulate.dat'
set border lw 1 lc rgb '#404040'
set grid back lw 1 lc rgb '#d0d0d0'
set multiplot layout 2,1 title 'grinding_scompi_ch4: 1000 W, last turns' noenhanced
set key top right
set xrange [3.9:4]
set arrow 1 from 3.9, graph 0 to 3.9, graph 1 nohead back dt 3 lc rgb '#b0b0b0'
set arrow 2 from 3.91, graph 0 to 3.91, graph 1 nohead back dt 3 lc rgb '#b0b0b0'
set arrow 3 from 3.92, graph 0 to 3.92, graph 1 nohead back dt 3 lc rgb '#b0b0b0'
set arrow 4 from 3.93, graph 0 to 3.93, graph 1 nohead back dt 3 lc rgb '#b0b0b0'
set arrow 5 from 3.94, graph 0 to 3.94, graph 1 nohead back dt 3 lc rgb '#b0b0b0'
set arrow 6 from 3.95, graph 0 to 3.95, graph 1 nohead back dt 3 lc rgb '#b0b0b0'
set arrow 7 from 3.96, graph 0 to 3.96, graph 1 nohead back dt 3 lc rgb '#b0b0b0'
set arrow 8 from 3.97, graph 0 to 3.97, graph 1 nohead back dt 3 lc rgb '#b0b0b0'
set arrow 9 from 3.98, graph 0 to 3.98, graph 1 nohead back dt 3 lc rgb '#b0b0b0'
set arrow 10 from 3.99, graph 0 to 3.99, graph 1 nohead back dt 3 lc rgb '#b0b0b0'
set arrow 11 from 4, graph 0 to 4, graph 1 nohead back dt 3 lc rgb '#b0b0b0'
unset xlabel
set ylabel 'depth below the uncut surface (mm)'
plot data using 1:2 with lines lw 2 lc rgb '#1f77b4' title 'wheel', \
  data using 1:3 with lines lw 1.5 dt 2 lc rgb '#d62728' title 'surface the previous turn left'
set xlabel 'time (s); dotted: wheel turns'
set ylabel 'normal force (N)'
plot data using 1:4 with lines lw 1.5 lc rgb '#1f77b4' title 'contact force (0.615 impacts per turn)'
unset multiplot
