# The error-against-cost chart of one mbgen_study scenario (docs/study.md):
#   gnuplot -e "dat='drop_lola.dat'; pareto='drop_lola_pareto.dat'; png='study_drop_lola.png';
#               plot_title='...'; reference_error=1e-12; per_backend=5" scripts/plot_study.gp
# dat holds one block per backend x integrator, backend by backend (a quoted title line, then
# cost, error, step rows; the step size varies along each curve): colour tells the integrator,
# point shape and dash the backend. The Pareto front is drawn over them, and the reference's own
# error as a floor: no point below it can be told from the reference.
set terminal pngcairo enhanced size 1100,800 font ",10"
set output png
set title plot_title noenhanced
set logscale xy
set format x "10^{%L}"
set format y "10^{%L}"
set xlabel "cost: CPU seconds per simulated second"
set ylabel "error: largest deviation of base position [m], orientation [rad], joints [rad, m]"
set grid
set yrange [reference_error / 10 : *]
set key outside right top noenhanced
stats dat using 1 nooutput
blocks = STATS_blocks
set arrow from graph 0, first reference_error to graph 1, first reference_error nohead dt 2 lc rgb "gray40"
set label "reference's own error" at graph 0.01, first reference_error * 1.6 tc rgb "gray40"
colour(i) = (i % per_backend) + 1
shape(i) = int(i / per_backend) * 2 + 4
plot for [i=0:blocks-1] dat index i using 1:2 with linespoints lc (colour(i)) dt int(i / per_backend) + 1 pt (shape(i)) ps 1.1 \
       title columnheader(1), \
     pareto using 1:2 with lines lw 5 lc rgb "#70000000" title "Pareto front"
