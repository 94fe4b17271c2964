# The picture of a robot's fitted SSVs (docs/ssv.md, "Fitting SSVs to meshes"), from the data of
# `mbgen fit-ssv --picture-data DIR`:
#   gnuplot -e "dir='DIR'; png='OUT.png'; plot_title='...'" scripts/plot_ssv_fit.gp
# Three views at the nominal pose: front (looking along -x, the robot's left on the right),
# side (looking along +y) and top (looking down). Meshes filled grey, each SSV primitive's
# silhouette (its projected core swept by a disc of its radius) outlined in red: every grey
# pixel must lie inside a red outline.
set terminal pngcairo enhanced size 1500,800 font ",10"
set output png
mesh = dir.'/mesh.dat'
ssv = dir.'/ssv.dat'
set multiplot layout 1,3 title plot_title noenhanced
set xtics 0.1
set size ratio -1
set grid
unset key
set style fill solid 1.0 noborder
set xlabel "y [m]"
set ylabel "z [m]"
set title "front (from +x)"
set xrange [*:*] reverse
plot mesh using 2:3 with filledcurves closed fc rgb "#b0b0b0", \
     ssv index 0 using 1:2 with lines lw 1 lc rgb "#d62728"
set xrange [*:*] noreverse
set xlabel "x [m]"
set title "side (from -y)"
plot mesh using 1:3 with filledcurves closed fc rgb "#b0b0b0", \
     ssv index 1 using 1:2 with lines lw 1 lc rgb "#d62728"
set ylabel "y [m]"
set title "top (from +z)"
plot mesh using 1:2 with filledcurves closed fc rgb "#b0b0b0", \
     ssv index 2 using 1:2 with lines lw 1 lc rgb "#d62728"
unset multiplot
