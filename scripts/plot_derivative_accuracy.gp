# Accuracy against step size and cost of the forward dynamics' derivatives (docs/derivatives.md):
# the CSV of `mbgen_derivative_accuracy` (robot,method,h,error,ns), one robot per chart.
#   gnuplot -e "csv='accuracy.csv'; robot='talos'; png='out.png'; plot_title='...'" scripts/plot_derivative_accuracy.gp
set datafile separator ","
set terminal pngcairo size 1000,650 font ",10" noenhanced
set output png
set grid
set logscale xy
set format x "1e%T"
set format y "1e%T"
set key at graph 0.02, graph 0.44 left top box opaque
set title plot_title
set xlabel "finite-difference step h"
set ylabel "relative error of the q and v derivatives (max-norm, worst of 8 states)"
# Each method's time per evaluation (ns, the same for every h) for the legend.
stats csv using ((strcol(1) eq robot && strcol(2) eq "central") ? $5 : NaN) nooutput
t_central = STATS_max
stats csv using ((strcol(1) eq robot && strcol(2) eq "forward") ? $5 : NaN) nooutput
t_forward = STATS_max
stats csv using ((strcol(1) eq robot && strcol(2) eq "analytic") ? $5 : NaN) nooutput
t_analytic = STATS_max
stats csv using ((strcol(1) eq robot && strcol(2) eq "analytic") ? $4 : NaN) nooutput
e_analytic = STATS_max
set xrange [1e-12:0.1]
set yrange [1e-16:1]
plot csv using ((strcol(1) eq robot && strcol(2) eq "central") ? $3 : NaN):4 with linespoints lw 2 pt 7 \
       title sprintf("central differences (4 n calls): %.1f us", t_central / 1000), \
     csv using ((strcol(1) eq robot && strcol(2) eq "forward") ? $3 : NaN):4 with linespoints lw 2 pt 5 \
       title sprintf("forward differences (2 n + 1 calls): %.1f us", t_forward / 1000), \
     e_analytic with lines lw 3 dt 2 \
       title sprintf("forward_dynamics_derivatives (and d/dtau): %.1f us, error %.1e", t_analytic / 1000, e_analytic)
