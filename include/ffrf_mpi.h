/* ffrf_mpi.h: the MPI_Comm convenience of the C API (MPI build, -DFFRF_MPI=ON). Kept apart so
 * that ffrf.h stays free of MPI: include this header only in an MPI host program. */
#ifndef FFRF_MPI_H
#define FFRF_MPI_H

#include <mpi.h>
#include "ffrf.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ffrf_case_set_communicator with a C communicator (converted by MPI_Comm_c2f). */
static inline int ffrf_case_set_mpi_comm(ffrf_case *c, MPI_Comm comm)
{
    return ffrf_case_set_communicator(c, (int)MPI_Comm_c2f(comm));
}

#ifdef __cplusplus
}
#endif

#endif /* FFRF_MPI_H */
