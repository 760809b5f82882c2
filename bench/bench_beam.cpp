// Benchmark of the beam solver pipeline (not a test): a cantilever of 10, 100, 1000 and 10000
// elements under a tip force, timed on the ranks it is started with. For each size, medians over
// several repetitions of:
//   assembly   residual + tangent of all elements into the Tpetra matrix (Assembler::assemble)
//   solve      one linear solve of the tangent system (Direct KLU2 by default)
//   iteration  one whole Newton iteration (assembly + solve + state update)
//   step       one whole load step T = 0 -> 1 (tip deflection ~5 % of the length), with its
//              Newton iteration count
// and the beam element's force and tangent alone, per element, as computed (written-out gradient,
// AD tangent) and by nested AD of the energy.
// Usage: bench_beam [--solver Direct|GMRES] [--repeat N] [--sizes 10,100,...]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include <Teuchos_XMLParameterListHelpers.hpp>
#include <Tpetra_Core.hpp>

#include "constraints/EnforcerRegistry.hpp"

#include "core/Assembler.hpp"
#include "core/LinearSolver.hpp"
#include "core/StaticSolver.hpp"
#include "elements/CorotationalBeam.hpp"
#include "input/Deck.hpp"

namespace {

using Clock = std::chrono::steady_clock;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::string deck(int elements, const std::string& solver) {
  // Elements as long as the section is high (10 x 10 section, element length 10, L = 10 n),
  // E = 30000, tip force P = 0.15 E I / L^2: linear tip deflection P L^3 / (3 E I) = 5 % of L.
  const double L = 10.0 * elements, P = 0.15 * 30000.0 * 1e4 / 12.0 / (L * L);
  std::ostringstream s;
  s.precision(17);
  s << R"XML(<ParameterList name="BeamContact"><ParameterList name="Beams"><ParameterList name="b">
    <Parameter name="Start" type="Array(double)" value="{0,0,0}"/><Parameter name="End" type="Array(double)" value="{)XML"
    << L << R"XML(,0,0}"/>
    <Parameter name="Elements" type="int" value=")XML"
    << elements << R"XML("/>
    <ParameterList name="Section"><Parameter name="Width" type="double" value="10"/><Parameter name="Height" type="double" value="10"/></ParameterList>
    <ParameterList name="Material"><Parameter name="Young's Modulus" type="double" value="30000"/><Parameter name="Poisson's Ratio" type="double" value="0.3"/></ParameterList>
  </ParameterList></ParameterList>
  <ParameterList name="Supports"><ParameterList name="clamp"><Parameter name="Beam" type="string" value="b"/><Parameter name="Node" type="string" value="start"/></ParameterList></ParameterList>
  <ParameterList name="Loads"><ParameterList name="tip"><Parameter name="Beam" type="string" value="b"/><Parameter name="Node" type="string" value="end"/>
    <Parameter name="Force" type="Array(double)" value="{0,0,)XML"
    << P << R"XML(}"/></ParameterList></ParameterList>
  <ParameterList name="Load Stepping"><Parameter name="Number of Increments" type="int" value="1"/></ParameterList>
  <ParameterList name="Linear Solver"><Parameter name="Type" type="string" value=")XML"
    << solver << R"XML("/></ParameterList>
</ParameterList>)XML";
  return s.str();
}

}  // namespace

int main(int argc, char** argv) {
  Tpetra::ScopeGuard scope(&argc, &argv);
  bc::constraints::registerBuiltinEnforcers();
  auto comm = Tpetra::getDefaultComm();
  const bool root = comm->getRank() == 0;
  std::string solverType = "Direct";
  int repeat = 7;
  std::vector<int> sizes = {10, 100, 1000, 10000};
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i], v = argv[i + 1];
    if (a == "--solver") solverType = v;
    else if (a == "--repeat") repeat = std::stoi(v);
    else if (a == "--sizes") {
      sizes.clear();
      std::istringstream in(v);
      std::string tok;
      while (std::getline(in, tok, ',')) sizes.push_back(std::stoi(tok));
    }
  }
  if (root) {
    std::printf("beam solver benchmark: %d rank(s), %s solver, medians of %d repetitions [ms]\n", comm->getSize(),
                solverType.c_str(), repeat);
    std::printf("%9s %8s %12s %12s %12s %12s %8s\n", "elements", "dofs", "assembly", "solve", "iteration", "step",
                "Newton");
  }
  for (int n : sizes) {
    auto problem = bc::input::buildProblem(*Teuchos::getParametersFromXmlString(deck(n, solverType)), "bench");
    auto linear =
        bc::core::makeLinearSolver(problem.linearSolver, {problem.model.initial.numDofs(), 0, comm->getSize()});
    bc::core::Assembler assembler(comm, problem.model);
    bc::core::State state = problem.model.initial;
    assembler.rebuild(state);
    std::vector<double> ta, ts, ti, tstep;
    int newton = 0;
    const int reps = n >= 10000 ? std::max(3, repeat / 2) : repeat;
    for (int r = 0; r < reps; ++r) {
      bc::core::State s = state;
      comm->barrier();
      auto t0 = Clock::now();
      assembler.assemble(s, 1.0, true);
      comm->barrier();
      auto t1 = Clock::now();
      bc::core::Vector rhs(assembler.ownedMap()), x(assembler.ownedMap());
      rhs.update(-1.0, *assembler.residual(), 0.0);
      linear->solve(assembler.matrix(), rhs, x);
      const auto inc = assembler.gatherToAll(x);
      s.applyIncrement(inc);
      comm->barrier();
      auto t2 = Clock::now();
      ta.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
      ts.push_back(std::chrono::duration<double, std::milli>(t2 - t1).count());
      ti.push_back(std::chrono::duration<double, std::milli>(t2 - t0).count());

      bc::core::StaticSolver solver(comm, problem.model, problem.solver, *linear);
      comm->barrier();
      auto t3 = Clock::now();
      const auto run =
          solver.run([](const bc::core::StepReport&, const bc::core::State&, const bc::core::Assembler&) {});
      comm->barrier();
      auto t4 = Clock::now();
      if (!run.completed && root) std::printf("step failed: %s\n", run.failure.c_str());
      newton = run.newtonIterations;
      tstep.push_back(std::chrono::duration<double, std::milli>(t4 - t3).count());
    }
    if (root)
      std::printf("%9d %8lld %12.3f %12.3f %12.3f %12.3f %8d\n", n, static_cast<long long>(state.numDofs()), median(ta),
                  median(ts), median(ti), median(tstep), newton);
  }
  if (root) {
    // The element kernel alone: force and tangent of one element at a bent and twisted state.
    using namespace bc::elements;
    const BeamElementData d =
        makeBeamElement({{0.0, 0.0, 0.0}}, {{10.0, 0.0, 0.0}}, {{0.0, 1.0, 0.0}}, 3e6, 1e6, 2.5e7, 2.5e7);
    BeamElementState s;
    s.x1 = {{0.0, 0.0, 0.0}};
    s.x2 = {{9.9, 0.8, 0.3}};
    s.R1 = expSO3(Vec3d{{0.1, 0.05, 0.08}});
    s.R2 = expSO3(Vec3d{{-0.05, 0.12, 0.15}});
    const auto perCall = [&](auto kernel) {
      std::vector<double> t;
      Vector12 f;
      Matrix12 K;
      double sum = 0.0;
      for (int r = 0; r < repeat; ++r) {
        const auto t0 = Clock::now();
        for (int k = 0; k < 10000; ++k) {
          kernel(d, s, f, K);
          sum += K[13];
        }
        t.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count() / 10000);
      }
      return sum != 0.0 ? median(t) : -1.0;
    };
    const double written = perCall(internalForceAndTangent), nested = perCall(internalForceAndTangentFromEnergy);
    std::printf(
        "beam element force and tangent [us per element]: %.2f (written-out gradient, AD tangent), %.2f "
        "(nested AD of the energy), ratio %.2f\n",
        written, nested, nested / written);
  }
  return 0;
}
