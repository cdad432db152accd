# Time-domain simulation, written by chatter 0.1.0.
# Reproduce or restyle: cd into this directory, edit, then run
#   gnuplot milling_benchmark_ae005_down_simulate_chatter.gp
# It reads milling_benchmark_ae005_down_simulate_chatter.dat and writes milling_benchmark_ae005_down_simulate_chatter.png (both by relative name).

fs = 14   # base font size (pt); title, key and labels are relative to it
set terminal pngcairo size 1200,800 enhanced font 'DejaVu Sans,'.fs linewidth 1.2
set output 'milling_benchmark_ae005_down_simulate_chatter.png'
set encoding utf8
set datafile missing '?'
data = 'milling_benchmark_ae005_down_simulate_chatter.dat'

c_x = '#1f77b4'
c_y = '#e07b00'
c_sample = '#c0392b'
c_spec = '#202020'
c_grid = '#c8c8c8'
c_label = '#3a3a3a'
set grid lc rgb c_grid lw 0.6
set border lw 0.8
set key top left horizontal opaque box lc rgb c_grid font ','.(fs-2)
set multiplot layout 3,1 title 'Milling benchmark, a_e/D = 0.05 down (case C), 17000 rev/min, 3.6 mm: chatter at 850 Hz, |{/Symbol m}| = 1' font ','.(fs+2) margins 0.09,0.97,0.07,0.91 spacing 0,0.09
set offsets 0, 0, graph 0.28, graph 0.04   # room for the key above the curves
set xrange [0:352.94118]
set xlabel 'time (ms)' offset 0,0.4
set ylabel 'relative displacement ({/Symbol m}m)'
plot data index 0 using 1:2 with lines lc rgb c_x lw 1 title 'x (feed direction)', \
     data index 1 using 1:2 with points pt 7 ps 0.45 lc rgb c_sample title 'x once per period'
set ylabel 'force on the tool (N)'
plot data index 0 using 1:5 with lines lc rgb c_y lw 1 title 'F_y', \
     data index 0 using 1:4 with lines lc rgb c_x lw 1 title 'F_x'
set offsets 0, 0, 0, 0
set xlabel 'frequency (Hz)' offset 0,0.4
set ylabel 'amplitude ({/Symbol m}m)'
set logscale y
set format y '10^{%L}'
set key top right vertical
set xrange [0:2305]
set yrange [5.473e-05:1.642e+04]   # headroom for the key
set arrow from 566.66667, graph 0 to 566.66667, graph 1 nohead dt 3 lw 0.8 lc rgb c_grid
set arrow from 1133.3333, graph 0 to 1133.3333, graph 1 nohead dt 3 lw 0.8 lc rgb c_grid
set arrow from 1700, graph 0 to 1700, graph 1 nohead dt 3 lw 0.8 lc rgb c_grid
set arrow from 2266.6667, graph 0 to 2266.6667, graph 1 nohead dt 3 lw 0.8 lc rgb c_grid
set label 'chatter 850 Hz' at 850.00034, graph 0.62 left offset 0.6,0 tc rgb c_sample font ','.(fs-1)
set arrow from 850.00034, graph 0 to 850.00034, graph 1 nohead lw 1.2 lc rgb c_sample
plot data index 2 using 1:2 with lines lc rgb c_spec lw 1 title 'relative displacement, last 100 periods', \
     data index 3 using 1:2 with points pt 6 ps 1.1 lw 1.2 lc rgb c_x title 'harmonics of 1/{/Symbol t} = 566.67 Hz (tooth passing; spindle in turning)'
unset multiplot
