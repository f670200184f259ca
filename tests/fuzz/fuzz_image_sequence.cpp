// libFuzzer target: the EuRoC/ASL image-sequence reader (read_image_sequence, vio/image_io.h).
//
// The reader takes a folder, so each input is laid out as one: byte 0 picks which optional files
// exist (bit 0 labels0/data.csv, bit 1 imu0/data.csv, bit 2 the ground truth), the rest is split
// at form feeds into the texts of cam0/data.csv, labels0/data.csv, imu0/data.csv and
// state_groundtruth_estimate0/data.csv. Both data/ folders hold empty files 0.png … 31.png (the
// reader only checks that an image exists), so inputs can name images that are there or not.
//
// Properties: a rejected input throws InputError naming a file of the folder (anything else, e.g.
// a std::filesystem error on a strange file name, is a bug); an accepted one has frames with
// strictly increasing stamps, t = t_ns · 1e-9, images that exist, labels (that exist) for all
// frames or none (all exactly when labels0 was given), and finite IMU samples and ground-truth poses.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "slamkit/core/error.h"
#include "slamkit/vio/image_io.h"

namespace {

namespace fs = std::filesystem;

[[noreturn]] void violation(const char* what) {
  std::fprintf(stderr, "fuzz property violated: %s\n", what);
  std::abort();
}

// One folder per process, made at the first input: mav0/{cam0,labels0}/data/{0..31}.png.
const fs::path& sequence_root() {
  static const fs::path root = [] {
    char pattern[] = "/tmp/slamkit_fuzz_images_XXXXXX";
    if (!mkdtemp(pattern)) violation("cannot create the fuzzing folder");
    const fs::path dir(pattern);
    for (const char* sub : {"mav0/cam0/data", "mav0/labels0/data", "mav0/imu0", "mav0/state_groundtruth_estimate0"}) {
      fs::create_directories(dir / sub);
      for (int k = 0; k < 32 && std::string(sub).find("/data") != std::string::npos; ++k)
        std::ofstream(dir / sub / (std::to_string(k) + ".png")).put('\0');
    }
    return dir;
  }();
  return root;
}

void place(const fs::path& path, bool present, const std::string& text) {
  std::error_code ec;
  fs::remove(path, ec);
  if (!present) return;
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) violation("cannot write a fuzzing file");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace slamkit;
  if (size == 0) return 0;
  const unsigned flags = data[0];
  std::vector<std::string> part(1);
  for (std::size_t i = 1; i < size; ++i) {
    if (data[i] == '\f' && part.size() < 4) part.emplace_back();
    else part.back().push_back(static_cast<char>(data[i]));
  }
  part.resize(4);
  const fs::path& root = sequence_root();
  const bool labels = flags & 1u, imu = flags & 2u, truth = flags & 4u;
  place(root / "mav0/cam0/data.csv", true, part[0]);
  place(root / "mav0/labels0/data.csv", labels, part[1]);
  place(root / "mav0/imu0/data.csv", imu, part[2]);
  place(root / "mav0/state_groundtruth_estimate0/data.csv", truth, part[3]);

  ImageSequence seq;
  try {
    seq = read_image_sequence(root.string());
  } catch (const InputError& e) {
    if (e.file().rfind(root.string(), 0) != 0) violation("an InputError that does not name a file of the folder");
    return 0;
  }
  if (seq.frames.empty()) violation("a sequence without frames accepted");
  if (seq.has_labels() != labels) violation("labels present without labels0, or missing with it");
  for (std::size_t k = 0; k < seq.frames.size(); ++k) {
    const ImageSequenceFrame& f = seq.frames[k];
    if (k > 0 && f.t_ns <= seq.frames[k - 1].t_ns) violation("stamps do not increase");
    if (f.t != static_cast<double>(f.t_ns) * 1e-9) violation("t is not t_ns * 1e-9");
    if (!fs::is_regular_file(f.image_path)) violation("an accepted frame names a missing image");
    if (f.label_path.empty() == labels) violation("labels for some frames only");
    if (labels && !fs::is_regular_file(f.label_path)) violation("an accepted frame names a missing label image");
  }
  for (const ImuMeasurement& m : seq.imu)
    if (!std::isfinite(m.stamp) || !m.gyro.allFinite() || !m.accel.allFinite()) violation("IMU sample not finite");
  for (std::size_t k = 0; k < seq.groundtruth.size(); ++k) {
    const TrajectorySample& s = seq.groundtruth[k];
    if (!std::isfinite(s.stamp) || !s.T_world_body.translation().allFinite() ||
        !s.T_world_body.rotation().quaternion().coeffs().allFinite())
      violation("ground-truth pose not finite");
  }
  return 0;
}
