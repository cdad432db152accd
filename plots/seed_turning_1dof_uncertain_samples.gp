# Uncertain lobes: probability of stability over spindle speed and depth, with quantile lobes,
# written by chatter 0.1.0.
# Reproduce or restyle: cd into this directory, edit, then run
#   gnuplot seed_turning_1dof_uncertain_samples.gp
# It reads seed_turning_1dof_uncertain_samples.dat and writes seed_turning_1dof_uncertain_samples.png.

fs = 14
set terminal pngcairo size 1200,800 enhanced font 'DejaVu Sans,'.fs linewidth 1.2
set output 'seed_turning_1dof_uncertain_samples.png'
set encoding utf8
data = 'seed_turning_1dof_uncertain_samples.dat'
set title 'Seed 1-DOF turning (case A), uncertain modes and K_f (analytic, 1000 samples)' noenhanced font ','.(fs+2)
set xlabel 'spindle speed (rev/min)'
set ylabel 'depth of cut (mm)'
set cblabel 'probability of stability'
set xrange [50:2000]
set yrange [0:6.9]
set cbrange [0:1]
set palette defined (0 '#b2182b', 0.5 '#fddbc7', 0.5 '#d1e5f0', 1 '#2166ac')
set key top right opaque box font ','.(fs-2)
set tics front
set border front
plot data index 0 using 1:2:3 with image notitle, \
  data index 1 using 1:3 with lines lw 2 dt 2 lc rgb '#6a00a8' title '95 % of samples stable below', \
  data index 1 using 1:4 with lines lw 2 dt 1 lc rgb '#e6a800' title '50 % of samples stable below', \
  data index 1 using 1:5 with lines lw 2 dt 2 lc rgb '#00796b' title '5 % of samples stable below', \
  data index 1 using 1:2 with lines lw 2.5 lc rgb '#000000' title 'nominal lobe'
