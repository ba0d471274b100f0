// libFuzzer target: the model-file reader on arbitrary bytes (`make fuzz`), each input given a
// valid checksum so that the values are validated, not just the checksum (a flipped byte fails
// that, which test_mesh_fuzz.cpp covers). A std::runtime_error (a one-line refusal) is the
// expected outcome; any other exception, a crash, a sanitizer report or an allocation beyond
// -rss_limit_mb is a bug.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "model/binary_file.h"
#include "msm_sim/model/model_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = "/tmp/msm_sim_model_fuzz_" + std::to_string(getpid()) + ".msm";
  std::string bytes(reinterpret_cast<const char*>(data), size);
  if (bytes.size() >= msm_sim::core::binary_file::kChecksumBytes) {
    const std::size_t body = bytes.size() - msm_sim::core::binary_file::kChecksumBytes;
    msm_sim::core::binary_file::PutU64(
        msm_sim::core::binary_file::Fnv1a(msm_sim::core::binary_file::kFnvOffsetBasis,
                                          reinterpret_cast<const unsigned char*>(bytes.data()),
                                          body),
        reinterpret_cast<unsigned char*>(&bytes[body]));
  }
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) return 0;
  std::fwrite(bytes.data(), 1, bytes.size(), file);
  std::fclose(file);
  try {
    msm_sim::core::LoadModel(path);
  } catch (const std::runtime_error&) {
    // A refusal, with its one-line reason.
  }
  std::remove(path.c_str());
  return 0;
}
