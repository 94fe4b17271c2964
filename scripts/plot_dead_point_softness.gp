# The continuation's chart of mbgen_study (docs/simulation.md, "Through a dead point"):
#   gnuplot -e "dat='dead_point_softness.dat'; png='study_dead_point_softness.png'; plot_title='...'; kkt=5.5e-10" \
#           scripts/plot_dead_point_softness.gp
# dat holds one block per time constant (a quoted title line, then 1 - d, deviation [rad], max |Phi| [m]).
stats dat using 1 nooutput  # before any range: it counts the blocks
blocks = STATS_blocks
set terminal pngcairo enhanced size 1000,700 font ",10"
set output png
set title plot_title noenhanced
set logscale xy
set format x "10^{%L}"
set format y "10^{%L}"
set xrange [*:*] reverse
set xlabel "1 - d: how soft the loop's rows are in a span (d the impedance; the default 1e-6)"
set ylabel "largest deviation of the crank angle from the exact motion over 1 s [rad]"
set grid
set key top right noenhanced
plot for [i=0:blocks-1] dat index i using 1:2 with linespoints lw 2 pt 7 title columnheader(1), \
     kkt with lines dt 2 lc rgb "gray40" title sprintf("KKT, every tree coordinate, exact constraint (%.1e rad)", kkt)
