#include "Regularization.hpp"

#include <cmath>
#include <stdexcept>

#include <Tpetra_Import_Util.hpp>

#include "SerialLu.hpp"

namespace bc::core {

int SaddlePointRegularization::regularize(const Matrix& A) {
  const auto a = A.getLocalMatrixHost();
  const auto& rowPtr = a.graph.row_map;
  const int n = static_cast<int>(A.getRowMap()->getNodeNumElements());
  if (locateDiagonals(A)) entryRow_ = rowMapColumns(A);
  std::vector<int> zero;
  for (int i = 0; i < n; ++i)
    if (diagonalEntry_[i] >= 0 && diagonal(a, i) == 0.0) zero.push_back(i);
  if (zero.empty()) return 0;
  std::vector<double> s(n, 0.0);
  for (int i : zero)
    for (auto k = rowPtr(i); k < rowPtr(i + 1); ++k) {
      const int j = entryRow_[k];
      if (j < 0 || j == i || a.values(k) == 0.0 || diagonal(a, j) == 0.0) continue;
      for (auto m = rowPtr(j); m < rowPtr(j + 1); ++m)
        if (entryRow_[m] == i) s[i] -= a.values(k) * a.values(m) / diagonal(a, j);
    }
  return setRegularized(A, s);
}

bool SaddlePointRegularization::locateDiagonals(const Matrix& A) {
  if (!regularizedGraph_.is_null() && regularizedGraph_ == A.getCrsGraph()) return false;
  regularizedGraph_ = A.getCrsGraph();
  const auto graph = A.getLocalMatrixHost().graph;
  const auto& rowMap = *A.getRowMap();
  const auto& colMap = *A.getColMap();
  const int n = static_cast<int>(rowMap.getNodeNumElements());
  diagonalEntry_.assign(n, -1);
  for (int i = 0; i < n; ++i)
    for (auto k = graph.row_map(i); k < graph.row_map(i + 1); ++k)
      if (colMap.getGlobalElement(graph.entries(k)) == rowMap.getGlobalElement(i))
        diagonalEntry_[i] = static_cast<long>(k);
  return true;
}

int SaddlePointRegularization::setRegularized(const Matrix& A, const std::vector<double>& s) {
  const auto values = A.getLocalMatrixHost().values;
  regularized_.assign(values.data(), values.data() + values.extent(0));
  int changed = 0;
  for (std::size_t i = 0; i < s.size(); ++i)
    if (diagonalEntry_[i] >= 0 && values(diagonalEntry_[i]) == 0.0 && s[i] != 0.0 && std::isfinite(s[i])) {
      regularized_[diagonalEntry_[i]] = s[i] / kRegularization;
      ++changed;
    }
  return changed;
}

int SaddlePointRegularization::regularizeOverRanks(const Matrix& A) {
  const auto a = A.getLocalMatrixHost();
  const auto& rowPtr = a.graph.row_map;
  const auto& entries = a.graph.entries;
  const auto& rowMap = *A.getRowMap();
  const auto& colMap = *A.getColMap();
  const MPI_Comm mpi = rawMpiComm(*rowMap.getComm());
  const int n = static_cast<int>(rowMap.getNodeNumElements());
  locateDiagonals(A);
  std::vector<Coupling> couplings;
  std::vector<int> owners;
  if (!localCouplings(A, couplings, owners)) return 0;
  // s_i = -sum_j a_ij a_ji / a_jj, with a_ij from this rank's row i.
  std::vector<double> s(n, 0.0);
  for (const Coupling& c : exchange(couplings, owners, mpi)) {
    const LO i = rowMap.getLocalElement(c.i);
    const LO j = colMap.getLocalElement(c.j);
    if (i < 0) throw std::logic_error("Direct (MUMPS): a multiplier's coupling sent to a rank without its row");
    if (j < 0) continue;  // a_ij is not in row i's pattern
    for (auto k = rowPtr(i); k < rowPtr(i + 1); ++k)
      if (entries(k) == j) s[i] -= a.values(k) * c.ratio;
  }
  int changed = setRegularized(A, s), allChanged = 0;
  MPI_Allreduce(&changed, &allChanged, 1, MPI_INT, MPI_SUM, mpi);
  return allChanged;
}

bool SaddlePointRegularization::localCouplings(const Matrix& A, std::vector<Coupling>& couplings,
                                               std::vector<int>& owners) {
  const auto a = A.getLocalMatrixHost();
  const auto& rowPtr = a.graph.row_map;
  const auto& entries = a.graph.entries;
  const auto& rowMap = *A.getRowMap();
  const auto& colMap = *A.getColMap();
  const MPI_Comm mpi = rawMpiComm(*rowMap.getComm());
  const int n = static_cast<int>(rowMap.getNodeNumElements());
  // The rows with a zero diagonal in the pattern, marked in the column map.
  Vector zero(A.getRowMap()), zeroColumn(A.getColMap());
  int zeros = 0, allZeros = 0;
  {
    auto z = zero.getDataNonConst();
    for (int i = 0; i < n; ++i)
      if (diagonalEntry_[i] >= 0 && diagonal(a, i) == 0.0) z[i] = 1.0, ++zeros;
  }
  MPI_Allreduce(&zeros, &allZeros, 1, MPI_INT, MPI_SUM, mpi);
  if (allZeros == 0) return false;
  const auto importer = A.getGraph()->getImporter();
  if (importer.is_null()) zeroColumn = zero;  // the column map is the domain (= row) map
  else zeroColumn.doImport(zero, *importer, Tpetra::INSERT);
  const auto zc = zeroColumn.getData();
  // Each column's owner: this rank, or for a column of another rank's row the importer's record.
  Teuchos::Array<int> columnOwner(colMap.getNodeNumElements(), rowMap.getComm()->getRank());
  if (!importer.is_null()) Tpetra::Import_Util::getPids(*importer, columnOwner, false);
  // For each of this rank's rows j with a nonzero diagonal, and each zero-diagonal row i among its
  // columns: (i, j, a_ji / a_jj), to go to the owner of row i.
  for (int j = 0; j < n; ++j) {
    const double d = diagonal(a, j);
    if (d == 0.0) continue;
    for (auto k = rowPtr(j); k < rowPtr(j + 1); ++k)
      if (zc[entries(k)] == 1.0 && a.values(k) != 0.0) {
        couplings.push_back({colMap.getGlobalElement(entries(k)), rowMap.getGlobalElement(j), a.values(k) / d});
        owners.push_back(columnOwner[entries(k)]);
      }
  }
  return true;
}

std::vector<SaddlePointRegularization::Coupling> SaddlePointRegularization::exchange(
    const std::vector<Coupling>& couplings, const std::vector<int>& owners, MPI_Comm mpi) {
  static_assert(sizeof(GO) == sizeof(long long), "global indices travel as MPI_LONG_LONG");
  int ranks = 0;
  MPI_Comm_size(mpi, &ranks);
  std::vector<int> sendCounts(ranks, 0), sendOffsets(ranks, 0), receiveCounts(ranks), receiveOffsets(ranks, 0);
  for (int o : owners) ++sendCounts[o];
  for (int r = 1; r < ranks; ++r) sendOffsets[r] = sendOffsets[r - 1] + sendCounts[r - 1];
  std::vector<GO> sendIds(2 * couplings.size());
  std::vector<double> sendRatios(couplings.size());
  {
    std::vector<int> next = sendOffsets;
    for (std::size_t t = 0; t < couplings.size(); ++t) {
      const int slot = next[owners[t]]++;
      sendIds[2 * slot] = couplings[t].i;
      sendIds[2 * slot + 1] = couplings[t].j;
      sendRatios[slot] = couplings[t].ratio;
    }
  }
  MPI_Alltoall(sendCounts.data(), 1, MPI_INT, receiveCounts.data(), 1, MPI_INT, mpi);
  for (int r = 1; r < ranks; ++r) receiveOffsets[r] = receiveOffsets[r - 1] + receiveCounts[r - 1];
  const int received = receiveOffsets[ranks - 1] + receiveCounts[ranks - 1];
  std::vector<GO> receiveIds(2 * static_cast<std::size_t>(received));
  std::vector<double> receiveRatios(received);
  MPI_Alltoallv(sendRatios.data(), sendCounts.data(), sendOffsets.data(), MPI_DOUBLE, receiveRatios.data(),
                receiveCounts.data(), receiveOffsets.data(), MPI_DOUBLE, mpi);
  for (int r = 0; r < ranks; ++r)
    sendCounts[r] *= 2, sendOffsets[r] *= 2, receiveCounts[r] *= 2, receiveOffsets[r] *= 2;
  MPI_Alltoallv(sendIds.data(), sendCounts.data(), sendOffsets.data(), MPI_LONG_LONG, receiveIds.data(),
                receiveCounts.data(), receiveOffsets.data(), MPI_LONG_LONG, mpi);
  std::vector<Coupling> arrived(received);
  for (int t = 0; t < received; ++t) arrived[t] = {receiveIds[2 * t], receiveIds[2 * t + 1], receiveRatios[t]};
  return arrived;
}

}  // namespace bc::core
