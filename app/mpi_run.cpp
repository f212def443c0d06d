// MPI runs (docs/cluster.md): rank 0 deals units of ensemble chunks to the ranks that ask and reduces them in chunk order.
#include "mpi_run.hpp"

#include "funnel/funnel.hpp"
#include "funnel/params.hpp"

#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <climits>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <future>
#include <iterator>
#include <list>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>
#include <type_traits>
#include <utility>

namespace funnel::cli {

namespace {

bool mpi_on = false;
int rank_ = 0;
int size_ = 1;

/// Messages between rank 0 and the others. Rank 0 sends Job (the options of a run_sweep), then
/// answers every Result with the next Unit (a range of tasks with the parameters of its points;
/// an empty unit: no work left), and at the end Stop (with its exit code). A rank asks for its
/// first units with empty Results.
enum Tag : int { Job = 1, Unit = 2, Result = 3, Stop = 4 };

/// True when an MPI launcher started this process (OpenMPI, PMIx, PMI-1/2 as used by MPICH,
/// Intel MPI and SLURM's srun, MVAPICH).
bool launched_by_mpi() {
  for (const char* var : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE", "MV2_COMM_WORLD_SIZE"}) {
    if (std::getenv(var) != nullptr) return true;
  }
  return false;
}

/// A task of `srun -n K` (K > 1) that has no MPI connection would run the whole command again
/// beside task 0, over the same output files: tasks other than 0 refuse (exit code 2).
void refuse_unconnected_task() {
  const char* task = std::getenv("SLURM_PROCID");
  if (task == nullptr || std::string(task) == "0") return;
  std::fprintf(stderr, "funnel: error: started as task %s of srun without an MPI connection: launch with "
               "srun --mpi=pmix (or pmi2), or mpirun (docs/cluster.md)\n", task);
  std::exit(2);
}

// ---- Bytes: the messages are the same binary on every rank, so plain values travel as bytes ----

class Writer {
 public:
  template <class T>
  void put(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    const auto* p = reinterpret_cast<const char*>(&value);
    bytes_.insert(bytes_.end(), p, p + sizeof(T));
  }
  template <class T>
  void put_vector(const std::vector<T>& values) {
    static_assert(std::is_trivially_copyable_v<T>);
    put(static_cast<std::uint64_t>(values.size()));
    const auto* p = reinterpret_cast<const char*>(values.data());
    bytes_.insert(bytes_.end(), p, p + values.size() * sizeof(T));
  }
  std::vector<char>& bytes() { return bytes_; }

 private:
  std::vector<char> bytes_;
};

class Reader {
 public:
  explicit Reader(const std::vector<char>& bytes) : p_(bytes.data()), end_(bytes.data() + bytes.size()) {}
  template <class T>
  T get() {
    static_assert(std::is_trivially_copyable_v<T>);
    T value;
    take(&value, sizeof(T));
    return value;
  }
  /// True when every byte has been read.
  bool done() const { return p_ == end_; }
  template <class T>
  std::vector<T> get_vector() {
    static_assert(std::is_trivially_copyable_v<T>);
    std::vector<T> values(static_cast<std::size_t>(get<std::uint64_t>()));
    take(values.data(), values.size() * sizeof(T));
    return values;
  }

 private:
  void take(void* out, std::size_t n) {
    if (static_cast<std::size_t>(end_ - p_) < n) throw std::runtime_error("MPI message shorter than expected");
    if (n == 0) return;  // an empty vector's data() may be null, which memcpy must not be given
    std::memcpy(out, p_, n);
    p_ += n;
  }
  const char* p_;
  const char* end_;
};

void put_chunk(Writer& w, const ChunkStats& c) {
  w.put(c.acc);
  w.put(c.exited);
  w.put(c.rest);
  w.put(c.trapped);
  w.put(c.capped);
  w.put(c.stalled);
  w.put(c.total_collisions);
  w.put(c.simulated_collisions);
  w.put(c.wear.bins);
  w.put(c.wear.widths);
  for (const WallWear& wall : c.wear.walls) {
    w.put_vector(wall.collisions);
    w.put_vector(wall.normal_impulse);
    w.put_vector(wall.impulse);
    w.put(wall.edge_collisions);
    w.put(wall.edge_normal_impulse);
    w.put(wall.edge_impulse);
  }
  w.put_vector(c.samples);
}

ChunkStats get_chunk(Reader& r) {
  ChunkStats c;
  c.acc = r.get<decltype(c.acc)>();
  c.exited = r.get<std::int64_t>();
  c.rest = r.get<std::int64_t>();
  c.trapped = r.get<std::int64_t>();
  c.capped = r.get<std::int64_t>();
  c.stalled = r.get<std::int64_t>();
  c.total_collisions = r.get<std::int64_t>();
  c.simulated_collisions = r.get<std::int64_t>();
  c.wear.bins = r.get<int>();
  c.wear.widths = r.get<decltype(c.wear.widths)>();
  for (WallWear& wall : c.wear.walls) {
    wall.collisions = r.get_vector<double>();
    wall.normal_impulse = r.get_vector<double>();
    wall.impulse = r.get_vector<double>();
    wall.edge_collisions = r.get<double>();
    wall.edge_normal_impulse = r.get<double>();
    wall.edge_impulse = r.get<double>();
  }
  c.samples = r.get_vector<Sample>();
  return c;
}

// ---- Point-to-point messages, waited for by polling: a waiting rank sleeps instead of spinning ----

constexpr auto poll_interval = std::chrono::microseconds(500);
/// Largest unit of work dealt at once, in samples per thread.
constexpr std::int64_t max_unit_samples = 65536;

int byte_count(const std::vector<char>& bytes) {
  if (bytes.size() > static_cast<std::size_t>(INT_MAX)) {
    throw std::runtime_error("MPI message of " + std::to_string(bytes.size()) +
                             " bytes is over 2 GB: use fewer samples per point with --per-sample");
  }
  return static_cast<int>(bytes.size());
}

/// Sends and returns when the message is on its way or received. Only the other ranks send
/// this way: rank 0 never blocks in a send (its Outbox), so a big message to it always completes.
void send(int to, Tag tag, std::vector<char>& bytes) {
  MPI_Send(bytes.data(), byte_count(bytes), MPI_BYTE, to, tag, MPI_COMM_WORLD);
}

/// Rank 0's sends, non-blocking: a rank sending it a big result while rank 0 sends it a big
/// unit would otherwise wait for each other forever.
class Outbox {
 public:
  Outbox() = default;
  Outbox(const Outbox&) = delete;
  Outbox& operator=(const Outbox&) = delete;
  ~Outbox() {
    while (!empty()) std::this_thread::sleep_for(std::chrono::microseconds(100));
  }
  void post(int to, Tag tag, std::vector<char> bytes) {
    auto& [buffer, request] = items_.emplace_back(std::move(bytes), MPI_REQUEST_NULL);
    MPI_Isend(buffer.data(), byte_count(buffer), MPI_BYTE, to, tag, MPI_COMM_WORLD, &request);
  }
  /// True when every message posted has left; frees the buffers of those that have.
  bool empty() {
    for (auto it = items_.begin(); it != items_.end();) {
      int done = 0;
      MPI_Test(&it->second, &done, MPI_STATUS_IGNORE);
      it = done != 0 ? items_.erase(it) : std::next(it);
    }
    return items_.empty();
  }

 private:
  std::list<std::pair<std::vector<char>, MPI_Request>> items_;
};

void send_empty(int to, Tag tag) {
  std::vector<char> none;
  send(to, tag, none);
}

struct Message {
  int from = 0;
  int tag = 0;
  std::vector<char> bytes;
};

/// The next message from `from` (or any rank), if one has arrived.
bool try_receive(int from, Message& m) {
  int arrived = 0;
  MPI_Status status;
  MPI_Iprobe(from, MPI_ANY_TAG, MPI_COMM_WORLD, &arrived, &status);
  if (arrived == 0) return false;
  int count = 0;
  MPI_Get_count(&status, MPI_BYTE, &count);
  m.from = status.MPI_SOURCE;
  m.tag = status.MPI_TAG;
  m.bytes.resize(static_cast<std::size_t>(count));
  MPI_Recv(m.bytes.data(), count, MPI_BYTE, m.from, m.tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  return true;
}

Message receive(int from) {
  Message m;
  while (!try_receive(from, m)) std::this_thread::sleep_for(poll_interval);
  return m;
}

// ---- The work: tasks, each one chunk of one point, dealt as units [first, last) of consecutive tasks ----

/// The tasks of a run in the order they are dealt: chain by chain (friction_chains, the points
/// of a chain consecutive), and within a chain chunk by chunk, its members' chunk c next to each
/// other, so that a unit gives run_chunks the same chunk of a chain's points. Task t is computed,
/// not stored (a sweep may have 10^8 tasks).
class ChainedTasks {
 public:
  ChainedTasks(const std::vector<std::vector<std::size_t>>& chains, std::int64_t chunks) {
    std::size_t point = 0;
    std::int64_t task = 0;
    for (const std::vector<std::size_t>& chain : chains) {
      spans_.push_back({point, task, chain.size()});
      point += chain.size();
      task += static_cast<std::int64_t>(chain.size()) * chunks;
    }
  }

  /// The chain of task t (an index into the chains).
  std::size_t chain(std::int64_t t) const {
    const auto after = std::upper_bound(spans_.begin(), spans_.end(), t,
                                        [](std::int64_t x, const Span& s) { return x < s.first_task; });
    return static_cast<std::size_t>(after - spans_.begin()) - 1;
  }

  /// Task t: (point in chain order, chunk).
  ChunkId operator[](std::int64_t t) const {
    const Span& s = spans_[chain(t)];
    const std::int64_t offset = t - s.first_task, size = static_cast<std::int64_t>(s.size);
    return {s.first_point + static_cast<std::size_t>(offset % size), offset / size};
  }

  /// Tasks [first, last).
  std::vector<ChunkId> ids(std::int64_t first, std::int64_t last) const {
    std::vector<ChunkId> out;
    for (std::int64_t t = first; t < last; ++t) out.push_back((*this)[t]);
    return out;
  }

 private:
  struct Span {
    std::size_t first_point;
    std::int64_t first_task;
    std::size_t size;
  };
  std::vector<Span> spans_;
};

/// A rank's answer to a unit: per point, its chunks computed (a consecutive range: a unit's
/// tasks are consecutive); those starting at chunk 0 folded into one prefix (fold_chunk), which
/// is what rank 0's reduction starts with anyway.
std::vector<char> encode_result(const std::vector<ChunkId>& ids, std::vector<ChunkStats> stats) {
  std::vector<std::size_t> order(ids.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return ids[a].point != ids[b].point ? ids[a].point < ids[b].point : ids[a].chunk < ids[b].chunk;
  });
  Writer w;
  for (std::size_t i = 0; i < order.size();) {
    const ChunkId& start = ids[order[i]];
    std::size_t j = i + 1;
    while (j < order.size() && ids[order[j]].point == start.point &&
           ids[order[j]].chunk == start.chunk + static_cast<std::int64_t>(j - i)) {
      ++j;
    }
    const bool folded = start.chunk == 0;
    w.put(static_cast<std::uint64_t>(start.point));
    w.put(start.chunk);
    w.put(static_cast<std::int64_t>(j - i));
    w.put(static_cast<char>(folded));
    if (folded) {
      ChunkStats prefix;
      for (std::size_t k = i; k < j; ++k) fold_chunk(prefix, std::move(stats[order[k]]));
      put_chunk(w, prefix);
    } else {
      for (std::size_t k = i; k < j; ++k) put_chunk(w, stats[order[k]]);
    }
    i = j;
  }
  return std::move(w.bytes());
}

/// Rank 0's side of one distributed run_sweep: the chunks back so far, reduced per point.
class Assembly {
 public:
  Assembly(const std::vector<Params>& points, const EnsembleOptions& options, const Progress& progress,
           const PointDone& point_done)
      : points_(points), options_(options), progress_(progress), point_done_(point_done),
        chunks_(chunk_count(options.samples)), tasks_(static_cast<std::int64_t>(points.size()) * chunks_),
        results_(points.size()), parts_(points.size()), prefix_(points.size(), 0),
        pending_(points.size(), chunks_) {}

  std::int64_t chunks() const { return chunks_; }
  std::int64_t tasks() const { return tasks_; }
  bool complete() const { return finished_ == tasks_; }
  std::vector<EnsembleResult> take_results() { return std::move(results_); }

  /// Chunks `first` .. `first + count - 1` of `point`; with `folded`, `stats` is one fold of them from chunk 0.
  void add(std::size_t point, std::int64_t first, std::int64_t count, bool folded, std::vector<ChunkStats> stats) {
    std::vector<ChunkStats>& parts = parts_[point];
    if (parts.empty()) parts.resize(static_cast<std::size_t>(chunks_));
    if (folded) {
      parts[0] = std::move(stats.front());
      prefix_[point] = count;
    } else {
      for (std::int64_t k = 0; k < count; ++k) parts[static_cast<std::size_t>(first + k)] = std::move(stats[static_cast<std::size_t>(k)]);
    }
    pending_[point] -= count;
    finished_ += count;
    if (pending_[point] == 0) {
      // reduce_chunks takes a folded prefix in place of its chunks: drop the slots it covers.
      if (prefix_[point] > 1) parts.erase(parts.begin() + 1, parts.begin() + prefix_[point]);
      results_[point] = reduce_chunks(points_[point], options_, std::move(parts));
      parts = {};
      if (point_done_) point_done_(point, results_[point]);
    }
    if (progress_) progress_(finished_, tasks_);
  }

  /// A unit computed here: one chunk per id.
  void add_local(const std::vector<ChunkId>& ids, std::vector<ChunkStats> stats) {
    for (std::size_t i = 0; i < ids.size(); ++i) {
      std::vector<ChunkStats> one;
      one.push_back(std::move(stats[i]));
      add(ids[i].point, ids[i].chunk, 1, false, std::move(one));
    }
  }

  /// A unit computed by another rank (encode_result).
  void add_message(const std::vector<char>& bytes) {
    Reader r(bytes);
    while (!r.done()) {
      const auto point = static_cast<std::size_t>(r.get<std::uint64_t>());
      const auto first = r.get<std::int64_t>();
      const auto count = r.get<std::int64_t>();
      const bool folded = r.get<char>() != 0;
      if (point >= points_.size() || first < 0 || count < 1 || first + count > chunks_) {
        throw std::runtime_error("MPI message with an invalid chunk range");
      }
      std::vector<ChunkStats> stats;
      for (std::int64_t k = 0; k < (folded ? 1 : count); ++k) stats.push_back(get_chunk(r));
      add(point, first, count, folded, std::move(stats));
    }
  }

 private:
  const std::vector<Params>& points_;
  const EnsembleOptions& options_;
  const Progress& progress_;
  const PointDone& point_done_;
  std::int64_t chunks_;
  std::int64_t tasks_;
  std::int64_t finished_ = 0;
  std::vector<EnsembleResult> results_;
  std::vector<std::vector<ChunkStats>> parts_;  ///< chunks of the points in progress
  std::vector<std::int64_t> prefix_;            ///< chunks folded into parts_[p][0], when > 0
  std::vector<std::int64_t> pending_;           ///< chunks not yet back, per point
};

/// A point's parameters as the values of the parameter table (the profile travels once, with
/// the job: every point of a run shares it).
std::vector<double> pack_params(const std::vector<Params>& points) {
  std::vector<double> values;
  for (const Params& p : points) {
    for (const ParameterInfo& info : parameters()) values.push_back(info.get(p));
  }
  return values;
}

std::vector<Params> unpack_params(const std::vector<double>& values,
                                  const std::shared_ptr<const ProfileSpec>& profile) {
  const std::size_t per = parameters().size();
  std::vector<Params> points;
  for (std::size_t i = 0; i + per <= values.size(); i += per) {
    Params p = default_params();
    for (std::size_t j = 0; j < per; ++j) parameters()[j].set(p, values[i + j]);
    p.profile = profile;
    points.push_back(p);
  }
  return points;
}

/// The profile of a run (or none) into a job message.
void put_profile(Writer& w, const std::shared_ptr<const ProfileSpec>& profile) {
  w.put(static_cast<int>(profile != nullptr));
  if (!profile) return;
  for (int i = 0; i < 2; ++i) {
    w.put_vector(profile->sides[i]);
    for (const auto* m : {&profile->e, &profile->mu, &profile->beta0}) {
      w.put(static_cast<int>((*m)[i].has_value()));
      w.put((*m)[i].value_or(0.0));
    }
  }
  w.put(static_cast<int>(profile->bottom.has_value()));
  w.put(profile->bottom.value_or(0.0));
  w.put_vector(std::vector<char>(profile->source.begin(), profile->source.end()));
}

std::shared_ptr<const ProfileSpec> get_profile(Reader& r) {
  if (r.get<int>() == 0) return nullptr;
  auto spec = std::make_shared<ProfileSpec>();
  for (int i = 0; i < 2; ++i) {
    spec->sides[i] = r.get_vector<Vec2>();
    for (auto* m : {&spec->e, &spec->mu, &spec->beta0}) {
      const bool has = r.get<int>() != 0;
      const double v = r.get<double>();
      if (has) (*m)[i] = v;
    }
  }
  const bool has_bottom = r.get<int>() != 0;
  const double bottom = r.get<double>();
  if (has_bottom) spec->bottom = bottom;
  const std::vector<char> source = r.get_vector<char>();
  spec->source.assign(source.begin(), source.end());
  return spec;
}

}  // namespace

MpiSession::MpiSession(int& argc, char**& argv) {
  if (!launched_by_mpi()) {
    refuse_unconnected_task();
    return;
  }
  int provided = 0;
  // Only the main thread calls MPI; rank 0 computes its own units on another thread.
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  mpi_on = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

MpiSession::~MpiSession() {
  if (mpi_on) MPI_Finalize();
}

namespace {

/// A rank's end: rank 0's exit code, once every rank has it.
int stopped(const Message& m) {
  MPI_Request barrier;
  MPI_Ibarrier(MPI_COMM_WORLD, &barrier);
  for (int done = 0; MPI_Test(&barrier, &done, MPI_STATUS_IGNORE), done == 0;) std::this_thread::sleep_for(poll_interval);
  return Reader(m.bytes).get<int>();
}

}  // namespace

int MpiSession::serve() {
  for (;;) {
    Message m = receive(0);
    if (m.tag == Stop) return stopped(m);
    if (m.tag != Job) continue;
    Reader job(m.bytes);
    EnsembleOptions options = job.get<EnsembleOptions>();
    options.cancel = nullptr;  // a pointer into rank 0's memory
    const std::shared_ptr<const ProfileSpec> profile = get_profile(job);
    const std::int64_t chunks = chunk_count(options.samples);
    // Two requests in flight: the next unit is here before this one is done, so the rank never
    // waits for rank 0. Each request is answered, in order; once with an empty unit, the rest
    // are empty too.
    int in_flight = 2;
    send_empty(0, Result);
    send_empty(0, Result);
    while (in_flight > 0) {
      m = receive(0);
      if (m.tag == Stop) return stopped(m);
      --in_flight;
      Reader unit(m.bytes);
      const auto first = unit.get<std::int64_t>();
      const auto last = unit.get<std::int64_t>();
      if (first == last) continue;  // no work left
      // The unit's tasks and points come with it: the points from the first it names, indexed
      // from 0 here.
      const auto point_base = static_cast<std::size_t>(unit.get<std::uint64_t>());
      const std::vector<ChunkId> ids = unit.get_vector<ChunkId>();
      const std::vector<Params> points = unpack_params(unit.get_vector<double>(), profile);
      std::vector<ChunkId> local = ids;
      for (ChunkId& id : local) {
        if (id.point < point_base || id.point - point_base >= points.size() || id.chunk < 0 || id.chunk >= chunks) {
          throw std::runtime_error("MPI unit with an invalid task");
        }
        id.point -= point_base;
      }
      std::vector<char> bytes = encode_result(ids, run_chunks(points, options, local));
      send(0, Result, bytes);
      ++in_flight;
    }
  }
}

void MpiSession::finish(int code) {
  if (!mpi_on) return;
  {
    Outbox out;
    for (int r = 1; r < size_; ++r) {
      Writer w;
      w.put(code);
      out.post(r, Stop, std::move(w.bytes()));
    }
  }
  // A rank may still be sending a result (rank 0 stopped in the middle of a job): receive and
  // drop everything until every rank has its Stop.
  MPI_Request barrier;
  MPI_Ibarrier(MPI_COMM_WORLD, &barrier);
  for (int done = 0; MPI_Test(&barrier, &done, MPI_STATUS_IGNORE), done == 0;) {
    Message m;
    if (!try_receive(MPI_ANY_SOURCE, m)) std::this_thread::sleep_for(poll_interval);
  }
}

std::string mpi_help() {
  return "Many processes: mpirun -np K funnel sweep|ensemble|paper ... deals grid points and chunks of ensembles "
         "to K ranks (each with --threads threads); rank 0 writes every output, the same bytes as one process; "
         "--resume works with any K (docs/cluster.md).";
}

int mpi_rank() { return rank_; }
int mpi_size() { return size_; }

std::vector<EnsembleResult> distributed_sweep(const std::vector<Params>& given, const EnsembleOptions& options,
                                              const Progress& progress, const PointDone& point_done) {
  if (size_ == 1) return run_sweep(given, options, progress, point_done);
  static_assert(std::is_trivially_copyable_v<EnsembleOptions>);
  // The points in chain order (points that differ only in mu next to each other, in ascending
  // mu), and the tasks chain by chain, chunk by chunk: a unit then gives run_chunks the same
  // chunk of a chain's points, which it runs together.
  const std::vector<std::vector<std::size_t>> chains = friction_chains(given, options);
  std::vector<std::size_t> order;
  std::vector<Params> points;
  order.reserve(given.size());
  points.reserve(given.size());
  for (const std::vector<std::size_t>& chain : chains) {
    for (const std::size_t i : chain) {
      order.push_back(i);
      points.push_back(given[i]);
    }
  }
  const std::int64_t chunks = chunk_count(options.samples);
  const ChainedTasks task_list(chains, chunks);
  const PointDone done_in_given_order = !point_done ? PointDone{} : [&](std::size_t i, const EnsembleResult& r) {
    point_done(order[i], r);
  };
  // Every point of a run shares one profile (the --geometry of a sweep), sent once with the job.
  const std::shared_ptr<const ProfileSpec> profile = points.empty() ? nullptr : points.front().profile;
  Assembly assembly(points, options, progress, done_in_given_order);
  Outbox out;
  for (int r = 1; r < size_; ++r) {
    Writer w;
    w.put(options);
    put_profile(w, profile);
    out.post(r, Job, std::move(w.bytes()));
  }
  // Unit size: about four units per rank, but at most 65 536 samples per thread (0.1 to 1 s of
  // work: finished points reach the partial file steadily), at least one chunk per thread, and
  // shrinking towards the end so that the ranks finish together.
  const std::int64_t tasks = assembly.tasks();
  const std::int64_t threads = resolve_threads(options.threads);
  const std::int64_t ranks = size_;
  const std::int64_t per_chunk = std::max<std::int64_t>(1, options.samples / assembly.chunks());
  const std::int64_t unit_max = std::max(
      threads, std::min((tasks + 4 * ranks - 1) / (4 * ranks), (max_unit_samples * threads + per_chunk - 1) / per_chunk));
  std::int64_t next = 0;
  auto deal = [&] {
    const std::int64_t left = tasks - next;
    std::int64_t last = next + std::min({left, unit_max, std::max(threads, (left + 2 * ranks - 1) / (2 * ranks))});
    // A unit ends where a chunk of a chain does: its members' chunk runs as one chain.
    while (last < tasks && task_list[last].chunk == task_list[last - 1].chunk &&
           task_list.chain(last) == task_list.chain(last - 1)) {
      ++last;
    }
    const std::pair<std::int64_t, std::int64_t> unit{next, last};
    next = last;
    return unit;
  };
  const auto unit_ids = [&](std::int64_t first, std::int64_t last) { return task_list.ids(first, last); };

  // Rank 0 computes units too, on a second thread; this thread only talks and reduces.
  std::future<std::vector<ChunkStats>> local;
  std::vector<ChunkId> local_ids;
  int released = 0;  // requests answered with an empty unit: two per rank end the job
  while (!assembly.complete() || released < 2 * (size_ - 1)) {
    bool busy = false;
    if (local.valid() && local.wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
      assembly.add_local(local_ids, local.get());
      busy = true;
    }
    if (!local.valid() && next < tasks) {
      const auto [first, last] = deal();
      local_ids = unit_ids(first, last);
      local = std::async(std::launch::async, [&points, &options, ids = local_ids] { return run_chunks(points, options, ids); });
    }
    Message m;
    if (try_receive(MPI_ANY_SOURCE, m) && m.tag == Result) {
      assembly.add_message(m.bytes);
      Writer w;
      const auto [first, last] = next < tasks ? deal() : std::pair<std::int64_t, std::int64_t>{0, 0};
      w.put(first);
      w.put(last);
      if (first < last) {
        // The unit's tasks, and its points: a range, as the tasks follow the points' order.
        const std::vector<ChunkId> ids = unit_ids(first, last);
        std::size_t low = ids.front().point, high = low;
        for (const ChunkId& id : ids) {
          low = std::min(low, id.point);
          high = std::max(high, id.point);
        }
        w.put(static_cast<std::uint64_t>(low));
        w.put_vector(ids);
        w.put_vector(pack_params(std::vector<Params>(points.begin() + static_cast<std::ptrdiff_t>(low),
                                                     points.begin() + static_cast<std::ptrdiff_t>(high) + 1)));
      }
      out.post(m.from, Unit, std::move(w.bytes()));
      released += first == last;
      busy = true;
    }
    out.empty();  // frees the buffers of the units that have left
    if (!busy) {
      if (local.valid()) {
        local.wait_for(poll_interval);
      } else {
        std::this_thread::sleep_for(poll_interval);
      }
    }
  }
  std::vector<EnsembleResult> in_order = assembly.take_results();
  std::vector<EnsembleResult> results(given.size());
  for (std::size_t i = 0; i < order.size(); ++i) results[order[i]] = std::move(in_order[i]);
  return results;
}

}  // namespace funnel::cli
