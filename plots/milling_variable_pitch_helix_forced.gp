# Forced response: tool path and machined wall, written by chatter 0.1.0.
# Reproduce or restyle: cd into this directory, edit, then run
#   gnuplot milling_variable_pitch_helix_forced.gp
# It reads milling_variable_pitch_helix_forced.dat and writes milling_variable_pitch_helix_forced.png.

fs = 14
set terminal pngcairo size 1200,800 enhanced font 'DejaVu Sans,'.fs linewidth 1.2
set output 'milling_variable_pitch_helix_forced.png'
set encoding utf8
set datafile missing '?'
data = 'milling_variable_pitch_helix_forced.dat'
set grid lc rgb '#d9d9d9' lw 0.6
set border lw 0.8
set multiplot layout 1,2 title '4-flute variable pitch, 30 deg helix, 12 mm, half slot climb, 9000 rev/min, 2 mm, 0.05 mm/tooth'."\n".'SLE 9.42 µm, peak to peak 13 / 35.4 µm (x / y), smallest chip -19.6 µm: teeth leave the cut, the linear limit does not hold' noenhanced font ','.(fs-1) margins 0.08,0.97,0.11,0.86 spacing 0.09,0
set key top left opaque box lc rgb '#d9d9d9' font ','.(fs-3)
set xlabel 'time over one period (ms)'
set ylabel 'relative displacement (µm)'
set xrange [0:6.666666667]
set offsets 0, 0, graph 0.25, graph 0.05
plot data index 0 using 1:4 with lines lw 6 lc rgb '#c7c7c7' title 'into the wall, -n_w·r', \
     data index 0 using 1:2 with lines lw 1.4 lc rgb '#1f77b4' title 'x (feed)', \
     data index 0 using 1:3 with lines lw 1.4 lc rgb '#ff7f0e' title 'y', \
     data index 1 using 1:2 with points pt 7 ps 1.3 lc rgb '#d62728' title 'tooth at the wall', \
     data index 1 using 1:2:(sprintf('%d', $3)) with labels offset 0,1.1 font ','.(fs-3) notitle
set offsets 0, 0, 0, 0
set xlabel 'surface location error (µm, + = material left)'
set ylabel 'height above the tool tip (mm)'
set xrange [-10.200269:15.29074]   # the nominal wall (0) always in view
set yrange [0:2]
set arrow from 0, graph 0 to 0, graph 1 nohead dt 3 lw 1 lc rgb '#7f7f7f'
plot data index 2 using 3:1 with lines lw 1 dt 2 lc rgb '#7f7f7f' title 'each tooth', \
     data index 2 using 4:1 with lines lw 1 dt 2 lc rgb '#7f7f7f' notitle, \
     data index 2 using 5:1 with lines lw 1 dt 2 lc rgb '#7f7f7f' notitle, \
     data index 2 using 6:1 with lines lw 1 dt 2 lc rgb '#7f7f7f' notitle, \
     data index 2 using 2:1 with lines lw 3 lc rgb '#2ca02c' title 'machined wall'
unset multiplot
