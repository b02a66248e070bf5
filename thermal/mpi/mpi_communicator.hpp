// The MPI implementation of thermal::Communicator (thermal/communicator.hpp), on MPI_COMM_WORLD. Linked only
// into what runs under mpirun; the caller initialises MPI first and finalises it after.
#pragma once

#include <memory>

#include "thermal/communicator.hpp"

namespace beadtwin::thermal {

// The communicator of every rank of the job. MPI must be initialised.
std::unique_ptr<Communicator> world_communicator();

}  // namespace beadtwin::thermal
