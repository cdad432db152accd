# Lobe surface: depth limit over spindle speed and tool position, written by chatter 0.1.0.
# Reproduce or restyle: cd into this directory, edit, then run
#   gnuplot milling_case_c_positions_surface.gp
# It reads milling_case_c_positions_surface.dat and writes milling_case_c_positions_surface.png.

fs = 14
set terminal pngcairo size 1200,800 enhanced font 'DejaVu Sans,'.fs linewidth 1.2
set output 'milling_case_c_positions_surface.png'
set encoding utf8
set datafile missing '?'
data = 'milling_case_c_positions_surface.dat'
depth_top = 10   # mm: the top of the colour scale (deeper limits take its colour)

# Contours of the chosen depths (mm), traced by gnuplot on the grid into a datablock.
set contour base
unset surface
set view map
set cntrparam linear
set cntrparam levels discrete 2,4,6,8
set table $contours
splot data index 0 using 1:2:3 with lines notitle
unset table
unset contour
set surface

set title 'Milling benchmark a_e/D = 0.05 down, tool mode along the path (case C positions) (sdm): lobe surface' noenhanced font ','.(fs+2)
set xlabel 'spindle speed (rev/min)'
set ylabel 'tool position (mm)'
set cblabel 'depth limit (mm)'
set xrange [5000:25000]
set yrange [0:120]
set cbrange [0:depth_top]
set palette defined (0 '#7a0c0c', 0.15 '#d7301f', 0.35 '#fc8d59', 0.55 '#fee090', 0.75 '#91bfdb', 1 '#2c5aa0')
set key top right opaque box font ','.(fs-2)
set tics front
set border front
# The top colour also marks deeper limits (and speeds stable to depth_max_mm).
set cbtics add (sprintf('≥ %g', depth_top) depth_top)
plot data index 0 using 1:2:($3 > depth_top ? depth_top : $3) with image notitle, \
  $contours using 1:2 with lines lw 1.6 lc rgb '#202020' title 'depth contours (2, 4, 6, 8 mm)', \
  $contours using 1:2:(sprintf('%g', $3)) every 25 with labels font ','.(fs-3) tc rgb '#202020' notitle, \
  data index 1 using 1:2 with lines lw 5 lc rgb '#202020' notitle, \
  data index 1 using 1:2 with linespoints lw 2.5 pt 7 ps 0.8 lc rgb '#ffffff' title 'best speed at each position'
