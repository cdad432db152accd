# Spindle speed variation map, written by chatter 0.1.0.
# Reproduce or restyle: cd into this directory, edit, then run
#   gnuplot ssv_case_a_map.gp
# It reads ssv_case_a_map.dat and writes ssv_case_a_map.png.

fs = 14
set terminal pngcairo size 1200,800 enhanced font 'DejaVu Sans,'.fs linewidth 1.2
set output 'ssv_case_a_map.png'
set encoding utf8
set datafile missing '?'
data = 'ssv_case_a_map.dat'
set border lw 1 lc rgb '#404040'
set grid back lw 1 lc rgb '#d0d0d0'
set title 'Case A turning with spindle speed variation (R_VA 0.1, R_VF 0.1): spectral radius per revolution with speed variation (sdm)' noenhanced
set xlabel 'frequency ratio R_VF (modulation / spindle frequency)' noenhanced
set ylabel 'amplitude ratio R_VA' noenhanced
set cblabel 'ln of the spectral radius per revolution (< 0 stable)'
set cbrange [-2.3025851:2.3025851]
set palette defined (-1 '#2166ac', -0.5 '#92c5de', 0 '#f7f7f7', 0.5 '#f4a582', 1 '#b2182b')
set view map
set key off
set grid front
set xrange [0.025:0.525]
set yrange [-0.025:0.325]
set contour base
unset surface
set cntrparam levels discrete 0
set table $boundary
splot data using 1:2:3
unset table
set surface
unset contour
plot data using 1:2:3 with image, $boundary using 1:2 with lines lw 2.5 lc rgb '#000000'
