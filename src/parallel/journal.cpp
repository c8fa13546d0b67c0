#include "parallel/journal.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace cs {
namespace {

namespace fs = std::filesystem;

constexpr char kBlockMagic[8] = {'C', 'S', 'J', 'B', 'L', 'K', '0', '1'};

// FNV-1a over the payload: catches a torn or truncated block file.
std::uint64_t checksum(const void* data, std::size_t bytes, std::uint64_t h = 1469598103934665603ull) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < bytes; ++i) h = (h ^ p[i]) * 1099511628211ull;
  return h;
}

// Writes `bytes` to `path` so that `path` either does not exist or holds all of them.
void write_atomically(const std::string& path, const std::string& bytes) {
  std::string tmp = path + ".tmp";
  int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw std::runtime_error("cannot create " + tmp + ": " + std::strerror(errno));
  std::size_t done = 0;
  while (done < bytes.size()) {
    ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      int err = errno;
      ::close(fd);
      throw std::runtime_error("cannot write " + tmp + ": " + std::strerror(err));
    }
    done += static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0 || ::close(fd) != 0)
    throw std::runtime_error("cannot flush " + tmp + ": " + std::strerror(errno));
  fs::rename(tmp, path);
}

std::string manifest_text(const RunIdentity& id) {
  std::ostringstream s;
  s << "contactsweep journal\nversion " << id.version << "\npoints " << id.points
    << "\nblock_size " << id.block_size << "\nspec_bytes " << id.spec_text.size() << "\n"
    << id.spec_text;
  return s.str();
}

}  // namespace

Journal::Journal(const std::string& output_path) : directory_(output_path + ".journal") {}

bool Journal::exists() const { return fs::exists(directory_); }

std::optional<RunIdentity> Journal::recorded_identity() const {
  std::ifstream in(directory_ + "/manifest", std::ios::binary);
  if (!in) return std::nullopt;
  RunIdentity id;
  std::string header, key;
  std::size_t spec_bytes = 0;
  std::getline(in, header);
  if (header != "contactsweep journal") return std::nullopt;
  if (!(in >> key >> id.version) || key != "version") return std::nullopt;
  if (!(in >> key >> id.points) || key != "points") return std::nullopt;
  if (!(in >> key >> id.block_size) || key != "block_size") return std::nullopt;
  if (!(in >> key >> spec_bytes) || key != "spec_bytes") return std::nullopt;
  in.get();  // the newline before the spec text
  id.spec_text.resize(spec_bytes);
  if (!in.read(id.spec_text.data(), static_cast<std::streamsize>(spec_bytes))) return std::nullopt;
  return id;
}

void Journal::create(const RunIdentity& id) const {
  fs::remove_all(directory_);
  fs::create_directories(directory_);
  write_atomically(directory_ + "/manifest", manifest_text(id));
}

std::string Journal::block_path(std::int64_t begin) const {
  return directory_ + "/block_" + std::to_string(begin) + ".bin";
}

void Journal::save(const BlockResults& block) const {
  std::string bytes(kBlockMagic, sizeof kBlockMagic);
  auto put = [&](const void* p, std::size_t n) { bytes.append(static_cast<const char*>(p), n); };
  std::int64_t header[3] = {block.range.begin, block.range.end,
                            static_cast<std::int64_t>(block.columns.size())};
  put(header, sizeof header);
  for (const auto& col : block.columns) {
    auto n = static_cast<std::int64_t>(col.size());
    put(&n, sizeof n);
  }
  for (const auto& col : block.columns) put(col.data(), col.size() * sizeof(double));
  std::uint64_t sum = checksum(bytes.data(), bytes.size());
  put(&sum, sizeof sum);
  write_atomically(block_path(block.range.begin), bytes);
}

bool Journal::load(BlockResults& block) const {
  std::ifstream in(block_path(block.range.begin), std::ios::binary);
  if (!in) return false;
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::size_t expected = sizeof kBlockMagic + 3 * sizeof(std::int64_t) +
                         block.columns.size() * sizeof(std::int64_t) + sizeof(std::uint64_t);
  for (const auto& col : block.columns) expected += col.size() * sizeof(double);
  if (bytes.size() != expected || std::memcmp(bytes.data(), kBlockMagic, sizeof kBlockMagic) != 0)
    return false;
  std::uint64_t sum;
  std::memcpy(&sum, bytes.data() + bytes.size() - sizeof sum, sizeof sum);
  if (sum != checksum(bytes.data(), bytes.size() - sizeof sum)) return false;
  const char* p = bytes.data() + sizeof kBlockMagic;
  std::int64_t header[3];
  std::memcpy(header, p, sizeof header);
  p += sizeof header;
  if (header[0] != block.range.begin || header[1] != block.range.end ||
      header[2] != static_cast<std::int64_t>(block.columns.size()))
    return false;
  for (const auto& col : block.columns) {
    std::int64_t n;
    std::memcpy(&n, p, sizeof n);
    p += sizeof n;
    if (n != static_cast<std::int64_t>(col.size())) return false;
  }
  for (auto& col : block.columns) {
    std::memcpy(col.data(), p, col.size() * sizeof(double));
    p += col.size() * sizeof(double);
  }
  return true;
}

void Journal::remove() const { fs::remove_all(directory_); }

}  // namespace cs
