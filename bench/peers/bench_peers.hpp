#pragma once

namespace mbgen::bench {
/// Registers the peer benchmarks against Pinocchio (bench/peers/README.md), after checking on
/// every state that both libraries compute the same thing; throws naming the first pair that
/// does not agree. Built only with -DMBGEN_PINOCCHIO_SOURCE=DIR.
void add_peer_benchmarks();
}  // namespace mbgen::bench
