# The stability map of mbgen_study (docs/study.md):
#   gnuplot -e "dat='stability_map.dat'; png='study_stability_map.png'; plot_title='...';
#               default_stiffness=2e7" scripts/plot_stability_map.gp
# dat holds one block per integrator (a quoted title line, then stiffness, largest stable step).
# The controller's 1 ms period caps the steps: a point on that line is stable at least there.
stats dat using 1 nooutput  # before any range: it counts the blocks
blocks = STATS_blocks
set terminal pngcairo enhanced size 1000,700 font ",10"
set output png
set title plot_title noenhanced
set logscale xy
set format x "10^{%L}"
set format y "10^{%L}"
set xlabel "contact stiffness k [N/m^{1.5}]"
set ylabel "largest stable step [s]"
set yrange [5e-6:2e-3]
set grid
set key bottom left noenhanced
set arrow from graph 0, first 1e-3 to graph 1, first 1e-3 nohead dt 2 lc rgb "gray40"
set label "controller period (the cap)" at graph 0.02, first 1.15e-3 tc rgb "gray40"
set arrow from first default_stiffness, graph 0 to first default_stiffness, graph 1 nohead dt 3 lc rgb "gray40"
set label "scene default" at first default_stiffness * 1.1, graph 0.05 tc rgb "gray40"
plot for [i=0:blocks-1] dat index i using 1:2 with linespoints lw 2 pt (i * 2 + 5) ps 1.3 title columnheader(1)
