// The checks of a built model that no single parameter shows: rigid-body motions the supports leave
// free, beams given twice, and the memory the model needs (internal to input/).
#pragma once
#include <cstddef>

#include "Deck.hpp"

namespace bc::input {

// What a model needs, against the memory this process may use. Measured (bench/bench_memory.py,
// docs/scale.md "Memory per element and per contact point"): the peak resident memory of a run on one
// rank with the default Direct solver (KLU2) grows by 16.5 kB per beam element (Example 1 with 2.5e4
// to 1e5 elements: 466 to 1646 MB) and, over the crossed layers' contact points (32 x 32 to 128 x 128,
// every point active), by 76 kB per point with Penalty and, with Lagrange multipliers, 170 kB from
// 32 x 32 to 64 x 64, 195 kB from 64 x 64 to 100 x 100 and at least 267 kB on average at 128 x 128
// (4.8 GB before KLU2's first factorization of the saddle point had ended, after 18 min: its factors
// grow faster than the points), above 74 MB for the program. Augmented Lagrange has Penalty's matrix; a plug-in's
// strategy is counted as Lagrange. A pair of All Pairs costs 100 bytes (its entry and the search's index: a network of
// 4000 fibres, 8e6 pairs, 791 MB above the same deck without contact). The estimate is checked before anything of the
// solver is allocated: while the beams are read (elements only), before All Pairs makes its pairs, and once the contact
// points at the start are known.
constexpr double kBytesPerElement = 17e3, kBaseBytes = 80e6;
constexpr double kBytesPerPair = 100.0;
constexpr double kBytesPerPointPenalty = 80e3, kBytesPerPointLagrange = 300e3;
// Refuses a model whose memory estimate exceeds the machine's.
void checkModelSize(std::size_t elements, std::size_t points = 0, double bytesPerPoint = 0.0, double pairs = 0.0);

// Throws an InputError naming the first structure (a beam, or beams sharing nodes) that its supports
// leave free to move as a rigid body.
void checkRigidBodyMotions(const Problem& p);
// Throws an InputError for two beams with the same Start and End.
void checkDuplicateBeams(const Problem& p);

}  // namespace bc::input
