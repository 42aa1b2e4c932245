#include "Cluster.h"

#include "../Error.h"

#include <algorithm>
#include <cstdlib>
#include <unistd.h>

#ifdef WAVEVCM_HAVE_MPI
#include <mpi.h>

#include <deque>
#include <memory>
#endif

namespace wv::cluster {

// Set by the MPI launchers in each process they start: OpenMPI's mpirun, and
// the PMI/PMIx process managers (MPICH's hydra, Slurm's srun).
static bool startedByLauncher()
{
    for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
        if (std::getenv(name)) return true;
    return false;
}

std::string hostName()
{
    char name[256] = {};
    if (::gethostname(name, sizeof name - 1) != 0) return "unknown host";
    return name;
}

#ifndef WAVEVCM_HAVE_MPI

void init(int*, char***)
{
    if (startedByLauncher())
        throw Error("started by an MPI launcher, but this wavevcm was built without MPI: every process would render "
                    "the whole job alone. Install libopenmpi-dev and rebuild (bash scripts/setup.sh)");
}
void finalize() {}
int rank() { return 0; }
int size() { return 1; }
void abortJob(int) {}
void barrier() {}
bool anyRank(bool value) { return value; }
double maxOverRanks(double value) { return value; }
void sumOnRoot(std::vector<double>&) {}
std::vector<int> gatherInts(int value) { return {value}; }
std::vector<double> gatherDoubles(double value) { return {value}; }
std::vector<std::string> gatherStrings(const std::string& value) { return {value}; }
void reportProgress(int) {}
void readProgress(std::vector<int>&) {}
void requestStop() {}
bool stopRequested() { return false; }

#else

static bool running = false; // MPI initialised by init()
static constexpr int progressTag = 1, stopTag = 2;

void init(int* argc, char*** argv)
{
    if (!startedByLauncher()) return;
    int provided = 0;
    if (MPI_Init_thread(argc, argv, MPI_THREAD_SERIALIZED, &provided) != MPI_SUCCESS)
        throw Error("MPI_Init_thread failed");
    running = true;
    if (provided < MPI_THREAD_SERIALIZED)
        throw Error("the MPI library does not support MPI_THREAD_SERIALIZED (several devices per rank call it "
                    "from their own threads)");
}

int rank()
{
    int r = 0;
    if (running) MPI_Comm_rank(MPI_COMM_WORLD, &r);
    return r;
}

int size()
{
    int s = 1;
    if (running) MPI_Comm_size(MPI_COMM_WORLD, &s);
    return s;
}

void abortJob(int exitCode)
{
    if (running && size() > 1) MPI_Abort(MPI_COMM_WORLD, exitCode);
}

void barrier()
{
    if (running) MPI_Barrier(MPI_COMM_WORLD);
}

bool anyRank(bool value)
{
    if (!running) return value;
    int in = value ? 1 : 0, out = 0;
    MPI_Allreduce(&in, &out, 1, MPI_INT, MPI_LOR, MPI_COMM_WORLD);
    return out != 0;
}

double maxOverRanks(double value)
{
    if (!running) return value;
    double out = value;
    MPI_Allreduce(&value, &out, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
    return out;
}

void sumOnRoot(std::vector<double>& values)
{
    if (!running) return;
    // MPI counts are int: reduce in chunks, so any image size works.
    const size_t chunk = size_t(1) << 28;
    for (size_t first = 0; first < values.size(); first += chunk) {
        int n = int(std::min(chunk, values.size() - first));
        if (rank() == 0)
            MPI_Reduce(MPI_IN_PLACE, values.data() + first, n, MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD);
        else
            MPI_Reduce(values.data() + first, nullptr, n, MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD);
    }
}

std::vector<int> gatherInts(int value)
{
    if (!running) return {value};
    std::vector<int> all(rank() == 0 ? size_t(size()) : 0);
    MPI_Gather(&value, 1, MPI_INT, all.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
    return all;
}

std::vector<double> gatherDoubles(double value)
{
    if (!running) return {value};
    std::vector<double> all(rank() == 0 ? size_t(size()) : 0);
    MPI_Gather(&value, 1, MPI_DOUBLE, all.data(), 1, MPI_DOUBLE, 0, MPI_COMM_WORLD);
    return all;
}

std::vector<std::string> gatherStrings(const std::string& value)
{
    if (!running) return {value};
    int length = int(value.size());
    std::vector<int> lengths = gatherInts(length);
    std::vector<int> offsets(lengths.size(), 0);
    int total = 0;
    for (size_t i = 0; i < lengths.size(); ++i) {
        offsets[i] = total;
        total += lengths[i];
    }
    std::string joined(size_t(total), '\0');
    MPI_Gatherv(value.data(), length, MPI_CHAR, joined.data(), lengths.data(), offsets.data(), MPI_CHAR, 0,
                MPI_COMM_WORLD);
    std::vector<std::string> all;
    for (size_t i = 0; i < lengths.size(); ++i) all.push_back(joined.substr(size_t(offsets[i]), size_t(lengths[i])));
    return all;
}

// Sends in flight, each with the buffer it reads.
struct PendingSend {
    std::unique_ptr<int> count;
    MPI_Request request;
};
static std::deque<PendingSend> pending;

static void freeSent()
{
    while (!pending.empty()) {
        int done = 0;
        MPI_Test(&pending.front().request, &done, MPI_STATUS_IGNORE);
        if (!done) break;
        pending.pop_front();
    }
}

static void sendInt(int value, int to, int tag)
{
    PendingSend send{std::make_unique<int>(value), MPI_REQUEST_NULL};
    MPI_Isend(send.count.get(), 1, MPI_INT, to, tag, MPI_COMM_WORLD, &send.request);
    pending.push_back(std::move(send));
}

void reportProgress(int iterations)
{
    if (!running || rank() == 0) return;
    freeSent();
    if (pending.size() >= 64) return; // rank 0 is not reading: progress is only informative, never wait for it
    sendInt(iterations, 0, progressTag);
}

static bool stopSent = false, stopReceived = false;

void requestStop()
{
    if (!running || stopSent) return;
    stopSent = true;
    if (rank() != 0) {
        sendInt(1, 0, stopTag);
        return;
    }
    for (int r = 1; r < size(); ++r) sendInt(1, r, stopTag);
}

bool stopRequested()
{
    if (!running || stopReceived) return stopReceived;
    int arrived = 0;
    MPI_Status status;
    MPI_Iprobe(MPI_ANY_SOURCE, stopTag, MPI_COMM_WORLD, &arrived, &status);
    if (!arrived) return false;
    int ignored = 0;
    MPI_Recv(&ignored, 1, MPI_INT, status.MPI_SOURCE, stopTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    stopReceived = true;
    if (rank() == 0) requestStop(); // pass it on to every rank
    return true;
}

void readProgress(std::vector<int>& iterationsByRank)
{
    if (!running || rank() != 0) return;
    for (;;) {
        int arrived = 0;
        MPI_Status status;
        MPI_Iprobe(MPI_ANY_SOURCE, progressTag, MPI_COMM_WORLD, &arrived, &status);
        if (!arrived) return;
        int count = 0;
        MPI_Recv(&count, 1, MPI_INT, status.MPI_SOURCE, progressTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        if (size_t(status.MPI_SOURCE) < iterationsByRank.size())
            iterationsByRank[size_t(status.MPI_SOURCE)] = std::max(iterationsByRank[size_t(status.MPI_SOURCE)], count);
    }
}

void finalize()
{
    if (!running) return;
    // Every rank has passed its last collective: what progress is still in
    // flight is read (rank 0) or let go (the others) before MPI ends.
    barrier();
    std::vector<int> ignored(size_t(size()), 0);
    readProgress(ignored);
    for (PendingSend& send : pending) {
        MPI_Request_free(&send.request);
        send.count.release(); // MPI may still read it: a few bytes left to the process's exit
    }
    pending.clear();
    MPI_Finalize();
    running = false;
}

#endif

} // namespace wv::cluster
