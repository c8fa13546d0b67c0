#include "parallel/block_stream.hpp"

#include <algorithm>
#include <chrono>
#include <thread>

#include "mpi/comm.hpp"

namespace cs {
namespace {

constexpr int kHeaderTag = 1, kValuesTag = 2;
// MPI counts are int: long columns go in pieces of at most 2^27 elements.
constexpr std::size_t kMessageElements = std::size_t{1} << 27;

template <class T>
std::vector<T> converted(const std::vector<double>& values) {
  std::vector<T> out(values.size());
  std::transform(values.begin(), values.end(), out.begin(),
                 [](double v) { return static_cast<T>(v); });
  return out;
}

}  // namespace

void write_values(OutputFile& file, const DatasetSpec& dataset,
                  const std::vector<PointRange>& ranges, const std::vector<double>& values) {
  switch (dataset.type) {
    case ElementType::float64: file.write(dataset.name, ranges, values.data()); break;
    case ElementType::int8: file.write(dataset.name, ranges, converted<std::int8_t>(values).data()); break;
    case ElementType::uint8: file.write(dataset.name, ranges, converted<std::uint8_t>(values).data()); break;
    case ElementType::int16: file.write(dataset.name, ranges, converted<std::int16_t>(values).data()); break;
    case ElementType::int32: file.write(dataset.name, ranges, converted<std::int32_t>(values).data()); break;
  }
}

// A block on its way to rank 0: its header and one request per message, alive until all are
// complete (MPI reads the buffers until then).
struct BlockStream::Sending {
  BlockResults* block;
  std::int64_t header[2];
  std::vector<MPI_Request> requests;
};

BlockStream::BlockStream(std::vector<Column> columns, OutputFile* file,
                         std::function<void()> on_failure, MPI_Comm comm)
    : columns_(std::move(columns)), file_(file), on_failure_(std::move(on_failure)) {
  if (!serial(comm)) {
    MPI_Comm_dup(comm, &comm_);
    rank_ = rank_of(comm_);
    ranks_ = size_of(comm_);
  }
}

BlockStream::~BlockStream() {
  int finalized = 0;
  if (comm_ != MPI_COMM_NULL) MPI_Finalized(&finalized);
  // Sends still pending only after an exception skipped finish(): the process is on its way to
  // MPI_Abort (main.cpp); a communicator with pending requests is not freed.
  if (comm_ != MPI_COMM_NULL && !finalized && sending_.empty()) MPI_Comm_free(&comm_);
}

void BlockStream::add(BlockResults& block) {
  std::lock_guard lock(mutex_);
  queued_.push_back(&block);
}

void BlockStream::release(BlockResults& block, const std::vector<Column>& columns) {
  for (const Column& c : columns) std::vector<double>().swap(block.columns[static_cast<std::size_t>(c.index)]);
}

void BlockStream::write(PointRange range, const std::vector<const std::vector<double>*>& values) {
  if (failure_) return;  // after a failure rank 0 only receives, so that no sender waits
  try {
    for (std::size_t k = 0; k < columns_.size(); ++k)
      write_values(*file_, columns_[k].dataset, {range}, *values[k]);
  } catch (...) {
    failure_ = std::current_exception();
    if (on_failure_) on_failure_();
  }
}

void BlockStream::write_own(BlockResults& block) {
  std::vector<const std::vector<double>*> values;
  for (const Column& c : columns_) values.push_back(&block.columns[static_cast<std::size_t>(c.index)]);
  write(block.range, values);
  release(block, columns_);
}

void BlockStream::start_send(BlockResults& block) {
  auto s = std::make_unique<Sending>();
  s->block = &block;
  s->header[0] = block.range.begin;
  s->header[1] = block.range.end;
  s->requests.emplace_back();
  MPI_Isend(s->header, 2, MPI_INT64_T, 0, kHeaderTag, comm_, &s->requests.back());
  for (const Column& c : columns_) {
    const std::vector<double>& values = block.columns[static_cast<std::size_t>(c.index)];
    for (std::size_t done = 0; done < values.size(); done += kMessageElements) {
      s->requests.emplace_back();
      MPI_Isend(values.data() + done,
                static_cast<int>(std::min(kMessageElements, values.size() - done)), MPI_DOUBLE,
                0, kValuesTag, comm_, &s->requests.back());
    }
  }
  sending_.push_back(std::move(s));
}

// In order: a block's columns are freed once every message of it has gone.
void BlockStream::complete_sends(bool wait) {
  while (!sending_.empty()) {
    Sending& s = *sending_.front();
    int done = 1;
    if (wait)
      MPI_Waitall(static_cast<int>(s.requests.size()), s.requests.data(), MPI_STATUSES_IGNORE);
    else
      MPI_Testall(static_cast<int>(s.requests.size()), s.requests.data(), &done,
                  MPI_STATUSES_IGNORE);
    if (!done) return;
    release(*s.block, columns_);
    sending_.pop_front();
  }
}

bool BlockStream::receive_one() {
  int waiting = 0;
  MPI_Status status;
  MPI_Iprobe(MPI_ANY_SOURCE, kHeaderTag, comm_, &waiting, &status);
  if (!waiting) return false;
  const int from = status.MPI_SOURCE;
  std::int64_t header[2];
  MPI_Recv(header, 2, MPI_INT64_T, from, kHeaderTag, comm_, MPI_STATUS_IGNORE);
  if (header[0] < 0) {  // that rank is done
    ++done_ranks_;
    return true;
  }
  const PointRange range{header[0], header[1]};
  const auto points = static_cast<std::size_t>(range.end - range.begin);
  // Each column as the sender's: points × width values (width: the trajectory's samples).
  std::vector<std::vector<double>> columns(columns_.size());
  std::vector<const std::vector<double>*> values;
  for (std::size_t k = 0; k < columns_.size(); ++k) {
    columns[k].resize(points * static_cast<std::size_t>(columns_[k].width));
    for (std::size_t done = 0; done < columns[k].size(); done += kMessageElements)
      MPI_Recv(columns[k].data() + done,
               static_cast<int>(std::min(kMessageElements, columns[k].size() - done)),
               MPI_DOUBLE, from, kValuesTag, comm_, MPI_STATUS_IGNORE);
    values.push_back(&columns[k]);
  }
  write(range, values);
  return true;
}

void BlockStream::poll() {
  std::deque<BlockResults*> ready;
  {
    std::lock_guard lock(mutex_);
    ready.swap(queued_);
  }
  for (BlockResults* block : ready) {
    if (rank_ == 0) write_own(*block);
    else start_send(*block);
  }
  if (rank_ == 0) {
    while (ranks_ > 1 && receive_one()) {
    }
  } else {
    complete_sends(false);
  }
}

void BlockStream::finish(const std::function<void()>& idle) {
  poll();
  if (rank_ != 0) {
    complete_sends(true);
    const std::int64_t done[2] = {-1, -1};
    MPI_Send(done, 2, MPI_INT64_T, 0, kHeaderTag, comm_);
    return;
  }
  while (done_ranks_ < ranks_ - 1) {
    if (receive_one()) continue;
    if (idle) idle();
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

}  // namespace cs
