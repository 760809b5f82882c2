// The assembled tangent against central differences of the assembled residual: the check of the
// whole pipeline's tangent (all contributions, or the contact alone), supports applied.
#pragma once
#include <vector>

#include "core/Assembler.hpp"
#include "support/CentralDifferences.hpp"

namespace bc::test {

// The tangent `a` assembles at state `s` and load factor T, column by column (K e_j, assembled again
// at `s` for each column), against central differences (h = 1e-6) of the residual; rows and columns
// of constrained dofs are skipped. Assembly is collective: every rank calls this.
inline CentralDifferenceError assembledTangentError(core::Assembler& a, const core::State& s, double T) {
  a.rebuild(s);
  a.assemble(s, T, true);
  const int n = static_cast<int>(s.numDofs());
  return centralDifferences(
      n, n, 1e-6,
      [&](int j, double h) {
        std::vector<double> du(n, 0.0);
        du[j] = h;
        core::State moved = s;
        moved.applyIncrement(du);
        a.assemble(moved, T, false);
        return a.gatherToAll(*a.residual());
      },
      [&](int j) {
        core::Vector ej(a.ownedMap()), col(a.ownedMap());
        if (a.ownsDof(j)) ej.replaceGlobalValue(j, 1.0);
        a.assemble(s, T, true);
        a.matrix()->apply(ej, col);
        return a.gatherToAll(col);
      },
      [&](int i) { return a.constrainedDofs().count(i) > 0; });
}

}  // namespace bc::test
