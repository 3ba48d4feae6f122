// Checkpoints of a run (`tissuebench run|leg --checkpoint-every S`, `--resume
// FILE`): a binary file holding a header - magic "TBCHECKP", format version,
// the kind of run ("run" or "leg"), the SHA-256 of its inputs and of its
// compiled model - then what the runner needs to continue bit-identically:
// its loop position and state, its accumulators, and a copy of every result
// written so far (ResultsSnapshot). Written whole-or-nothing (a temporary and
// a rename, msd/io/atomic_file.hpp); a checkpoint of another input, another
// kind or another version is refused with a message naming the file.
#pragma once

#include "tbio/results_file.hpp"

#include "msd/core/types.hpp"
#include "msd/model/model.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace tbio {

/// 2: the state carries BDF2's history (State::x_prev, v_prev, dt_prev) and the joints.
constexpr std::uint32_t kCheckpointVersion = 2;

class CheckpointWriter {
 public:
  CheckpointWriter(const std::string& kind, const std::string& input_hash, const std::string& model_hash);
  void integer(std::int64_t v);
  void number(double v);
  void numbers(const std::vector<double>& v);
  void text(const std::string& s);
  void points(const msd::Points& p);
  void snapshot(const ResultsSnapshot& s);
  /// The whole of an msd::State: positions, velocities, time, step, the
  /// integrators' memories (velocity Verlet's acceleration, BDF2's history), joints.
  void state(const msd::State& s);
  /// Writes the file (whole or nothing). Throws msd::Error naming it.
  void save(const std::string& path) const;

 private:
  std::string bytes_;
};

/// What a checkpoint was written for: the kind of run and the SHA-256 of its
/// inputs and of its model.
struct CheckpointHeader {
  std::string kind, input_hash, model_hash;
};

/// The header of the checkpoint at `path`. Throws msd::Error naming the file
/// when it cannot be read, is not a checkpoint or has another format version.
CheckpointHeader read_checkpoint_header(const std::string& path);

class CheckpointReader {
 public:
  /// Reads `path` and checks its header against this run; throws msd::Error
  /// naming the file and what differs.
  CheckpointReader(const std::string& path, const std::string& kind, const std::string& input_hash,
                   const std::string& model_hash);
  std::int64_t integer();
  double number();
  std::vector<double> numbers();
  std::string text();
  msd::Points points();
  ResultsSnapshot snapshot();
  msd::State state();
  /// Throws unless every byte was read.
  void finish() const;
  const std::string& path() const { return path_; }

 private:
  friend CheckpointHeader read_checkpoint_header(const std::string& path);
  /// Reads `path`, checks the magic and the version, and reads the header.
  CheckpointReader(const std::string& path, CheckpointHeader& header);
  void take(void* out, size_t n);
  std::string path_, bytes_;
  size_t at_ = 0;
  CheckpointHeader header_;
};

/// SHA-256 of a model's defining arrays (rest positions, masses), so a resume
/// against a differently meshed or built model is refused.
std::string fingerprint(const msd::Points& rest_positions, const Eigen::VectorXd& mass);

}  // namespace tbio
