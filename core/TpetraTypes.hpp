// The Tpetra types of this build (Debian's Trilinos 13.2: Scalar double, LocalOrdinal int,
// GlobalOrdinal long long, Serial node) in one place.
#pragma once
#include <Teuchos_Comm.hpp>
#include <Teuchos_DefaultMpiComm.hpp>
#include <Teuchos_RCP.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Map.hpp>
#include <Tpetra_MultiVector.hpp>
#include <Tpetra_Vector.hpp>

namespace bc::core {

using Scalar = double;
using Map = Tpetra::Map<>;
using LO = Map::local_ordinal_type;
using GO = Map::global_ordinal_type;
using Node = Map::node_type;
using Matrix = Tpetra::CrsMatrix<Scalar, LO, GO, Node>;
using Vector = Tpetra::Vector<Scalar, LO, GO, Node>;
using MultiVector = Tpetra::MultiVector<Scalar, LO, GO, Node>;
using Operator = Tpetra::Operator<Scalar, LO, GO, Node>;
using Comm = Teuchos::Comm<int>;

// The MPI communicator under `comm`, or MPI_COMM_NULL when it is not an MPI one (a serial build's).
inline MPI_Comm rawMpiComm(const Comm& comm) {
  const auto* mpi = dynamic_cast<const Teuchos::MpiComm<int>*>(&comm);
  return mpi ? MPI_Comm(*mpi->getRawMpiComm()) : MPI_COMM_NULL;
}

}  // namespace bc::core
