# Program check, written by chatter 0.1.0.
# Reproduce or restyle: cd here and run gnuplot program_pocket.gp

fs = 14
set terminal pngcairo size 1200,800 enhanced font 'DejaVu Sans,'.fs linewidth 1.2
set output 'program_pocket.png'
set encoding utf8
set datafile missing '?'
data = 'program_pocket.dat'
set multiplot layout 2,1 title 'pocket.ngc: 54 cutting blocks, 0 unstable, 38 overloaded' noenhanced font ','.(fs+2)
set grid lc rgb '#c8c8c8'
set key top right opaque box font ','.(fs-3)
set xlabel 'cutting time (s)'
set ylabel 'margin = limit / depth'
set yrange [0:4.2]
set y2label 'spindle power (kW)'
set y2tics
set ytics nomirror
set arrow 1 from graph 0, first 1 to graph 1, first 1 nohead lw 2 lc rgb '#c0392b' dt 2
plot data index 0 using 1:2 with lines lw 2.5 lc rgb '#1a4d80' title 'margin (limit / depth; 1 = chatter)', \
  data index 0 using 1:3 axes x1y2 with lines lw 1.5 lc rgb '#e07b00' title 'power (kW)', \
  1 axes x1y2 with lines dt 3 lc rgb '#e07b00' title 'machine power'
unset arrow 1
unset y2tics
unset y2label
set ytics mirror
set autoscale xy
set xlabel 'x (mm)'
set ylabel 'y (mm)'
set size ratio -1
set cblabel 'margin'
set cbrange [0:4]
set palette defined (0 '#7a0c0c', 0.9 '#d7301f', 1.0 '#fc8d59', 1.5 '#fee090', 2.5 '#91bfdb', 4 '#2c5aa0')
set key below
plot data index 2 using 1:2 with lines lw 7 lc rgb '#90000000' title 'overloaded (power, torque or speed)', data index 1 using 1:2:3 with lines lw 2 lc palette title 'toolpath by margin (air = top colour)'
unset multiplot
