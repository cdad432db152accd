# Receptance (FRF) chart, written by chatter 0.1.0.
# Reproduce or restyle: cd into this directory, edit, then run
#   gnuplot seed_turning_1dof_uncertain_frf.gp
# It reads seed_turning_1dof_uncertain_frf.dat and writes seed_turning_1dof_uncertain_frf.png (both by relative name).

fs = 14   # base font size (pt); title, key and labels are relative to it
set terminal pngcairo size 1200,800 enhanced font 'DejaVu Sans,'.fs linewidth 1.2
set output 'seed_turning_1dof_uncertain_frf.png'
set encoding utf8
set datafile missing '?'
data = 'seed_turning_1dof_uncertain_frf.dat'

# Colours
c_tool = '#1f77b4'; c_workpiece = '#e07b00'; c_relative = '#202020'
# Column of body b (0 tool, 1 workpiece, 2 relative), term t (0 xx, 1 yy), part p
# (0 magnitude, 1 phase, 2 real, 3 imaginary)
col(b, t, p) = 2 + 12*t + 4*b + p

set multiplot title 'Seed 1-DOF turning (case A), uncertain modes and K_f' noenhanced font ','.(fs+3)
set lmargin at screen 0.11; set rmargin at screen 0.975
set border lw 1 lc rgb '#404040'
set grid xtics ytics mxtics mytics back lw 1 lc rgb '#c8c8c8', lw 0.5 lc rgb '#e4e4e4'
set xrange [47.11:188.44]
set mxtics 2
set key at screen 0.54, screen 0.9 center center horizontal reverse Left samplen 2 width -1 font ','.(fs-1)

# Upper panel
set tmargin at screen 0.86; set bmargin at screen 0.515
set format x ''; unset xlabel
set logscale y
set format y '10^{%L}'
set mytics 10
set ylabel 'magnitude |G| (m/N)'
plot \
  data using 1:col(2,0,0) with lines lw 3.2 lc rgb c_relative title 'relative = tool + workpiece', \
  data using 1:col(1,0,0) with lines lw 1.6 lc rgb c_workpiece title 'workpiece', \
  keyentry with lines lt nodraw title 'tool: rigid'

# Lower panel
unset key
set tmargin at screen 0.465; set bmargin at screen 0.10
set format x '%g'
set xlabel 'frequency (Hz)'
unset logscale y
set format y '%g'
set yrange [-180:0]
set ytics 45
set mytics 3
set ylabel 'phase (deg)'
plot \
  data using 1:col(2,0,1) with lines lw 3.2 lc rgb c_relative title 'relative = tool + workpiece', \
  data using 1:col(1,0,1) with lines lw 1.6 lc rgb c_workpiece title 'workpiece', \
  keyentry with lines lt nodraw title 'tool: rigid'
unset multiplot
