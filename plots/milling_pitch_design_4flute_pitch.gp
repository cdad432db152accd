# Pitch design over a speed band (chatter design-pitch), written by chatter 0.1.0.
# Reproduce or restyle: cd into this directory, edit, then run
#   gnuplot milling_pitch_design_4flute_pitch.gp
# It reads milling_pitch_design_4flute_pitch.dat and writes milling_pitch_design_4flute_pitch.png.

fs = 14
set terminal pngcairo size 1200,800 enhanced font 'DejaVu Sans,'.fs linewidth 1.2
set output 'milling_pitch_design_4flute_pitch.png'
set encoding utf8
set datafile missing '?'
data = 'milling_pitch_design_4flute_pitch.dat'
set border lw 1 lc rgb '#404040'
set grid back lw 1 lc rgb '#d0d0d0'
set title '4-flute end mill, 30 deg helix, 12 mm, half slot climb (equal pitch): equal vs designed pitch (sdm)' noenhanced
set xlabel 'spindle speed (rev/min)'
set ylabel 'depth limit (mm)'
set xrange [6600:8000]
set yrange [0:9.81985]
set key bottom right box opaque noenhanced
c_equal = '#606060'; c_designed = '#d95f02'
set arrow 1 from graph 0, first 2.490333813 to graph 1, first 2.490333813 nohead dt (6,4) lw 1.5 lc rgb c_equal
set label 1 sprintf('worst, equal: %.3g mm', 2.490333813) at graph 0.01, first 2.490333813 offset 0, 0.6 tc rgb c_equal
set arrow 2 from graph 0, first 5.979757365 to graph 1, first 5.979757365 nohead dt (6,4) lw 1.5 lc rgb c_designed
set label 2 sprintf('worst, designed: %.3g mm', 5.979757365) at graph 0.01, first 5.979757365 offset 0, 0.6 tc rgb c_designed
plot data using 1:2 with linespoints lw 2 pt 7 ps 0.5 lc rgb c_equal title 'equal pitch', \
     data using 1:3 with linespoints lw 2.5 pt 7 ps 0.5 lc rgb c_designed title 'designed: 52.67/77.56/102.4/127.3 deg'
