# The plot of one mbgen_sim run (docs/simulation.md):
#   gnuplot -e "csv='drop.csv'; png='drop.png'; plot_title='...'; contact=1" scripts/plot_simulation.gp
# Contact scenarios: base and CoM height; normal forces per contact link over the weight m g;
# penetration, the deepest end stop and the loops' violation max |Phi|. Swing: energy, energy balance, loop violation.
set datafile separator ","
set terminal pngcairo size 1000,900 font ",10" noenhanced
set output png
set grid
set multiplot layout 3,1 title plot_title
set xlabel "t [s]"
lowcut(x) = x > 1e-17 ? x : 1e-17
if (contact) {
  set ylabel "height [m]"
  plot csv using "t":"base_z" with lines lw 2 title "base z", csv using "t":"com_z" with lines lw 2 title "CoM z"
  stats csv using 1 nooutput
  links = STATS_columns - 14
  stats csv using (column("normal_force")/column("weight")) nooutput
  set ylabel "normal force / m g"
  set yrange [0:2.5]
  # Many contact links (a whole-body fall): the per-link curves without a legend.
  if (links > 8) {
    unset key
    set title sprintf("impact peak %.1f m g (clipped); one curve per contact link (%d), black: total", STATS_max, links)
  } else {
    set title sprintf("impact peak %.1f m g (clipped)", STATS_max)
  }
  plot for [i=15:*] csv using "t":(column(i)/column("weight")) with lines title columnhead(i), \
       csv using "t":(column("normal_force")/column("weight")) with lines lw 2 lc rgb "black" title "total"
  unset title
  set key
  set autoscale y
  set y2label "loop violation max |Phi| [m, rad]"
  set y2tics
  set logscale y2
  set y2range [1e-17:1e-2]
  set format y2 "%.0e"
  set ylabel "penetration [mm; end stop: mrad]"
  plot csv using "t":(column("max_penetration")*1000) with lines lw 2 title "largest penetration (ground)", \
       csv using "t":(column("stop_penetration")*1000) with lines lw 2 title "deepest end stop", \
       csv using "t":(lowcut(column("closure_residual"))) axes x1y2 with lines title "loop violation (right)"
} else {
  set ylabel "energy [J]"
  stats csv using "energy" nooutput
  pad = 0.05 * (abs(STATS_max) + abs(STATS_min)) + 1e-9
  set yrange [STATS_min - pad : STATS_max + pad]
  plot csv using "t":"energy" with lines lw 2 title "energy (kinetic + gravity)"
  set autoscale y
  set ylabel "energy - energy(0) [J]"
  set format y "%.1e"
  plot csv using "t":"energy_balance" with lines lw 2 title "energy balance"
  set ylabel "loop violation max |Phi| [m, rad]"
  set logscale y
  set yrange [1e-17:1e-2]
  plot csv using "t":(lowcut(column("closure_residual"))) with lines lw 2 title "loop violation"
}
unset multiplot
