# Diametral error along the part, written by chatter 0.1.0.
# Reproduce or restyle: cd into this directory, edit, then run
#   gnuplot coupled_tool1_workpiece1_diametral.gp
# It reads coupled_tool1_workpiece1_diametral.dat and writes coupled_tool1_workpiece1_diametral.png.

fs = 14
set terminal pngcairo size 1200,800 enhanced font 'DejaVu Sans,'.fs linewidth 1.2
set output 'coupled_tool1_workpiece1_diametral.png'
set encoding utf8
set datafile missing '?'
data = 'coupled_tool1_workpiece1_diametral.dat'
set grid lc rgb '#d9d9d9' lw 0.6
set border lw 0.8
set title 'Coupled turning, tool 1 x workpiece 1 (case B): diametral error, 1 mm deep, 0.2 mm/rev' noenhanced font ','.(fs+2)
set key top left opaque box lc rgb '#d9d9d9' font ','.(fs-2)
set xlabel 'tool position (mm)'
set ylabel 'µm'
plot data using 1:2 with linespoints lw 2.4 pt 7 ps 0.7 lc rgb '#202020' title 'diametral error 2δ', \
     data using 1:3 with lines lw 1.2 dt 2 lc rgb '#1f77b4' title 'deflection δ along the radius'
