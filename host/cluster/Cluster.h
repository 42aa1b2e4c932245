// The processes of one render started by mpirun (OpenMPI), each a "rank":
// what they say to each other, and nothing else of MPI. A process that no MPI
// launcher started, or a build without MPI (libopenmpi-dev absent at build
// time), is a job of one rank, and every call below is then trivial, so the
// render command has one code path.
//
// MPI is initialised only when a launcher's variables are in the environment
// (OMPI_COMM_WORLD_SIZE, PMI_SIZE, PMIX_RANK): a plain `wavevcm render` never
// starts an MPI runtime.
#pragma once

#include <string>
#include <vector>

namespace wv::cluster {

// From main(): initialises MPI when a launcher started this process (with
// MPI_THREAD_SERIALIZED: MPI calls come from one thread at a time, not
// always the main one). Throws wv::Error when mpirun started it but the
// build has no MPI: each process would render the whole job alone.
void init(int* argc, char*** argv);
// At exit (MPI_Finalize); harmless without MPI.
void finalize();

int rank();
int size();
std::string hostName();

// Ends every rank of the job at once with `exitCode` (MPI_Abort): after one
// rank's error, so that none waits forever for it. Returns only without MPI.
void abortJob(int exitCode);

// Collective calls: every rank must make the same ones in the same order.
void barrier();
bool anyRank(bool value);                   // logical or over the ranks, on every rank
double maxOverRanks(double value);           // on every rank
void sumOnRoot(std::vector<double>& values); // rank 0 gets the element-wise sums (others' left unspecified)
std::vector<int> gatherInts(int value);      // rank 0 gets one per rank, in rank order; others: empty
std::vector<double> gatherDoubles(double value);
std::vector<std::string> gatherStrings(const std::string& value);

// Progress, point to point, never blocking: a rank other than 0 reports how
// many iterations it has finished; rank 0 reads what has arrived.
void reportProgress(int iterations);
// Rank 0: the newest count from each rank (entry 0 untouched).
void readProgress(std::vector<int>& iterationsByRank);

// Stopping early (Ctrl-C, SIGTERM), never blocking: mpirun signals one rank
// after another, waiting for each to end, so the ranks tell each other. A
// rank that is told to stop calls requestStop(); every rank then sees
// stopRequested() within its next poll (rank 0 passes a request on to all).
void requestStop();
bool stopRequested(); // sticky once true

} // namespace wv::cluster
