#include "tbio/checkpoint.hpp"

#include "tbio/sha256.hpp"

#include "msd/io/atomic_file.hpp"

#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>

namespace tbio {

namespace {

const char kMagic[8] = {'T', 'B', 'C', 'H', 'E', 'C', 'K', 'P'};

}  // namespace

CheckpointWriter::CheckpointWriter(const std::string& kind, const std::string& input_hash,
                                   const std::string& model_hash) {
  bytes_.assign(kMagic, sizeof kMagic);
  integer(kCheckpointVersion);
  text(kind);
  text(input_hash);
  text(model_hash);
}

void CheckpointWriter::integer(std::int64_t v) { bytes_.append(reinterpret_cast<const char*>(&v), sizeof v); }
void CheckpointWriter::number(double v) { bytes_.append(reinterpret_cast<const char*>(&v), sizeof v); }

void CheckpointWriter::numbers(const std::vector<double>& v) {
  integer(static_cast<std::int64_t>(v.size()));
  bytes_.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(double));
}

void CheckpointWriter::text(const std::string& s) {
  integer(static_cast<std::int64_t>(s.size()));
  bytes_.append(s);
}

void CheckpointWriter::points(const msd::Points& p) {
  integer(p.cols());
  bytes_.append(reinterpret_cast<const char*>(p.data()), static_cast<size_t>(p.size()) * sizeof(double));
}

void CheckpointWriter::state(const msd::State& s) {
  points(s.x);
  points(s.v);
  number(s.t);
  integer(s.step);
  points(s.a);
  integer(s.a_valid ? 1 : 0);
  points(s.x_prev);
  points(s.v_prev);
  number(s.dt_prev);
  std::vector<double> joints;
  for (const msd::HingeState& j : s.joints) joints.insert(joints.end(), {j.angle, j.velocity});
  numbers(joints);
}

void CheckpointWriter::snapshot(const ResultsSnapshot& s) {
  integer(static_cast<std::int64_t>(s.rows.size()));
  for (const auto& r : s.rows) numbers(r);
  integer(static_cast<std::int64_t>(s.fields.size()));
  for (const auto& [name, f] : s.fields) {
    text(name);
    numbers(f.time);
    integer(static_cast<std::int64_t>(f.displacement.size()));
    for (const auto& frame : f.displacement) {
      integer(static_cast<std::int64_t>(frame.size()));
      bytes_.append(reinterpret_cast<const char*>(frame.data()), frame.size() * sizeof(frame[0]));
    }
  }
}

void CheckpointWriter::save(const std::string& path) const {
  msd::write_file_atomically(path, [&](std::ostream& out) { out.write(bytes_.data(), static_cast<std::streamsize>(bytes_.size())); });
}

CheckpointReader::CheckpointReader(const std::string& path, CheckpointHeader& header) : path_(path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw msd::Error(path + ": cannot read the checkpoint");
  bytes_.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  if (bytes_.size() < sizeof kMagic || std::memcmp(bytes_.data(), kMagic, sizeof kMagic) != 0)
    throw msd::Error(path + ": not a tissuebench checkpoint");
  at_ = sizeof kMagic;
  const std::int64_t version = integer();
  if (version != kCheckpointVersion)
    throw msd::Error(path + ": checkpoint format version " + std::to_string(version) + ", this program reads " +
                     std::to_string(kCheckpointVersion));
  header.kind = text();
  header.input_hash = text();
  header.model_hash = text();
}

CheckpointReader::CheckpointReader(const std::string& path, const std::string& kind, const std::string& input_hash,
                                   const std::string& model_hash)
    : CheckpointReader(path, header_) {
  if (header_.kind != kind) throw msd::Error(path + ": a checkpoint of '" + header_.kind + "', not of '" + kind + "'");
  if (header_.input_hash != input_hash)
    throw msd::Error(path + ": the checkpoint was written for different input (its spec/scene, calibration or "
                            "options differ from this run's); refused");
  if (header_.model_hash != model_hash)
    throw msd::Error(path + ": the checkpoint was written for a different model (mesh or masses differ); refused");
}

CheckpointHeader read_checkpoint_header(const std::string& path) {
  CheckpointHeader h;
  const CheckpointReader r(path, h);
  return h;
}

void CheckpointReader::take(void* out, size_t n) {
  if (n > bytes_.size() - at_) throw msd::Error(path_ + ": the checkpoint is truncated");
  std::memcpy(out, bytes_.data() + at_, n);
  at_ += n;
}

std::int64_t CheckpointReader::integer() {
  std::int64_t v = 0;
  take(&v, sizeof v);
  return v;
}

double CheckpointReader::number() {
  double v = 0;
  take(&v, sizeof v);
  return v;
}

namespace {

size_t checked_count(std::int64_t n, size_t item, size_t left, const std::string& path) {
  if (n < 0 || static_cast<std::uint64_t>(n) > left / std::max<size_t>(item, 1))
    throw msd::Error(path + ": the checkpoint is truncated or damaged");
  return static_cast<size_t>(n);
}

}  // namespace

std::vector<double> CheckpointReader::numbers() {
  const size_t n = checked_count(integer(), sizeof(double), bytes_.size() - at_, path_);
  std::vector<double> v(n);
  take(v.data(), n * sizeof(double));
  return v;
}

std::string CheckpointReader::text() {
  const size_t n = checked_count(integer(), 1, bytes_.size() - at_, path_);
  std::string s(n, '\0');
  take(s.data(), n);
  return s;
}

msd::Points CheckpointReader::points() {
  const size_t n = checked_count(integer(), 3 * sizeof(double), bytes_.size() - at_, path_);
  msd::Points p(3, static_cast<Eigen::Index>(n));
  take(p.data(), n * 3 * sizeof(double));
  return p;
}

msd::State CheckpointReader::state() {
  msd::State s;
  s.x = points();
  s.v = points();
  s.t = number();
  s.step = integer();
  s.a = points();
  s.a_valid = integer() != 0;
  s.x_prev = points();
  s.v_prev = points();
  s.dt_prev = number();
  const std::vector<double> joints = numbers();
  if (joints.size() % 2 != 0) throw msd::Error(path_ + ": a checkpoint's joint states come in pairs (angle, velocity)");
  for (size_t j = 0; j + 1 < joints.size(); j += 2) s.joints.push_back({joints[j], joints[j + 1]});
  return s;
}

ResultsSnapshot CheckpointReader::snapshot() {
  ResultsSnapshot s;
  const size_t rows = checked_count(integer(), sizeof(std::int64_t), bytes_.size() - at_, path_);
  for (size_t r = 0; r < rows; ++r) s.rows.push_back(numbers());
  const size_t sets = checked_count(integer(), sizeof(std::int64_t), bytes_.size() - at_, path_);
  for (size_t k = 0; k < sets; ++k) {
    const std::string name = text();
    ResultsSnapshot::Frames& f = s.fields[name];
    f.time = numbers();
    const size_t frames = checked_count(integer(), sizeof(std::int64_t), bytes_.size() - at_, path_);
    for (size_t i = 0; i < frames; ++i) {
      const size_t n = checked_count(integer(), 3 * sizeof(double), bytes_.size() - at_, path_);
      std::vector<std::array<double, 3>> frame(n);
      take(frame.data(), n * sizeof(frame[0]));
      f.displacement.push_back(std::move(frame));
    }
  }
  return s;
}

void CheckpointReader::finish() const {
  if (at_ != bytes_.size()) throw msd::Error(path_ + ": the checkpoint has unexpected trailing bytes");
}

std::string fingerprint(const msd::Points& rest_positions, const Eigen::VectorXd& mass) {
  std::string b(reinterpret_cast<const char*>(rest_positions.data()),
                static_cast<size_t>(rest_positions.size()) * sizeof(double));
  b.append(reinterpret_cast<const char*>(mass.data()), static_cast<size_t>(mass.size()) * sizeof(double));
  return sha256_hex(b);
}

}  // namespace tbio
