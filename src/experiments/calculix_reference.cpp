#include "msm_sim/experiments/calculix_reference.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

extern char** environ;

namespace msm_sim::core {
namespace {

namespace fs = std::filesystem;

constexpr const char* kJob = "cantilever";
constexpr const char* kInstallHint = "install calculix-ccx (scripts/install_dependencies.sh)";

void Require(bool condition, const std::string& message) {
  if (!condition) throw std::invalid_argument("CalculiX cantilever: " + message);
}

std::string Str(double value) {
  std::ostringstream text;
  text << value;
  return text.str();
}

void Validate(const CalculixCantilever& box) {
  const bool sizes_ok = std::isfinite(box.length) && std::isfinite(box.width) &&
                        std::isfinite(box.height) && box.length > 0.0 && box.width > 0.0 &&
                        box.height > 0.0;
  Require(sizes_ok, "length, width and height must be finite and > 0 (got " + Str(box.length) +
                        ", " + Str(box.width) + ", " + Str(box.height) + " m)");
  Require(std::isfinite(box.youngs) && box.youngs > 0.0,
          "Young's modulus must be finite and > 0 (got " + Str(box.youngs) + " Pa)");
  // The bounds of an isotropic solid's stable range: CalculiX would factor a singular matrix.
  Require(box.poisson > -1.0 && box.poisson < 0.5,
          "Poisson's ratio must be in (-1, 0.5) (got " + Str(box.poisson) + ")");
  Require(std::isfinite(box.force), "force must be finite (got " + Str(box.force) + " N)");
  const std::string counts = std::to_string(box.elements_x) + ", " +
                             std::to_string(box.elements_y) + ", " + std::to_string(box.elements_z);
  Require(box.elements_x >= 1 && box.elements_y >= 1 && box.elements_z >= 1,
          "elements along x, y and z must each be >= 1 (got " + counts + ")");
  // Each count is checked before the product so that the product cannot overflow.
  const bool each_ok = box.elements_x <= kMaxCalculixElements &&
                       box.elements_y <= kMaxCalculixElements &&
                       box.elements_z <= kMaxCalculixElements;
  Require(each_ok && static_cast<long>(box.elements_x) * box.elements_y * box.elements_z <=
                         kMaxCalculixElements,
          "elements " + counts + " are more than the limit of " +
              std::to_string(kMaxCalculixElements) + " in all");
  Require(!box.executable.empty(), "the CalculiX executable's name is empty");
  Require(!std::isnan(box.timeout_seconds), "the timeout must be a number");
}

// CalculiX numbers nodes from 1; x varies fastest.
long NodeNumber(const CalculixCantilever& box, int i, int j, int k) {
  return 1 + i +
         static_cast<long>(box.elements_x + 1) * (j + static_cast<long>(box.elements_y + 1) * k);
}

long NodeCount(const CalculixCantilever& box) {
  return static_cast<long>(box.elements_x + 1) * (box.elements_y + 1) * (box.elements_z + 1);
}

void WriteNodes(const CalculixCantilever& box, std::ostream& deck) {
  deck << "*NODE, NSET=NALL\n";
  for (int k = 0; k <= box.elements_z; ++k) {
    for (int j = 0; j <= box.elements_y; ++j) {
      for (int i = 0; i <= box.elements_x; ++i) {
        deck << NodeNumber(box, i, j, k) << ", " << box.length * i / box.elements_x << ", "
             << box.width * j / box.elements_y << ", " << box.height * k / box.elements_z << "\n";
      }
    }
  }
}

// CalculiX's C3D8 order: the face of lower z counter-clockwise seen from +z (so that the element's
// Jacobian is positive), then the face above it in the same order.
void WriteElements(const CalculixCantilever& box, std::ostream& deck) {
  deck << "*ELEMENT, TYPE=C3D8I, ELSET=EALL\n";
  long element = 1;
  for (int k = 0; k < box.elements_z; ++k) {
    for (int j = 0; j < box.elements_y; ++j) {
      for (int i = 0; i < box.elements_x; ++i) {
        deck << element++;
        for (int layer = 0; layer < 2; ++layer) {
          deck << ", " << NodeNumber(box, i, j, k + layer) << ", "
               << NodeNumber(box, i + 1, j, k + layer) << ", "
               << NodeNumber(box, i + 1, j + 1, k + layer) << ", "
               << NodeNumber(box, i, j + 1, k + layer);
        }
        deck << "\n";
      }
    }
  }
}

// The clamp: every node of the face x = 0, all three displacements fixed.
void WriteClamp(const CalculixCantilever& box, std::ostream& deck) {
  deck << "*NSET, NSET=CLAMP\n";
  for (int k = 0; k <= box.elements_z; ++k) {
    for (int j = 0; j <= box.elements_y; ++j) deck << NodeNumber(box, 0, j, k) << ",\n";
  }
  deck << "*BOUNDARY\nCLAMP, 1, 3\n";
}

// Consistent nodal loads of a uniform traction on the end face: for bilinear faces each element
// face's share of the force, force * (face area / end-face area), goes in equal quarters to its
// corners. Summed per node, so that each node has one *CLOAD line.
void WriteLoads(const CalculixCantilever& box, std::ostream& deck) {
  const int ny = box.elements_y;
  const int nz = box.elements_z;
  std::vector<double> load((ny + 1) * (nz + 1), 0.0);
  const double face_area = (box.width / ny) * (box.height / nz);
  const double quarter = 0.25 * box.force * face_area / (box.width * box.height);
  for (int k = 0; k < nz; ++k) {
    for (int j = 0; j < ny; ++j) {
      for (int corner = 0; corner < 4; ++corner) {
        load[(j + corner % 2) + (ny + 1) * (k + corner / 2)] += quarter;
      }
    }
  }
  deck << "*CLOAD\n";
  for (int k = 0; k <= nz; ++k) {
    for (int j = 0; j <= ny; ++j) {
      deck << NodeNumber(box, box.elements_x, j, k) << ", 3, " << -load[j + (ny + 1) * k] << "\n";
    }
  }
}

// Removes the directory it made, whatever happens to the run.
class TemporaryDirectory {
 public:
  TemporaryDirectory() {
    std::string pattern = (fs::temp_directory_path() / "msm_sim_calculix_XXXXXX").string();
    if (mkdtemp(pattern.data()) == nullptr) {
      throw std::runtime_error("CalculiX cantilever: cannot create a directory in " +
                               fs::temp_directory_path().string() + ": " + std::strerror(errno));
    }
    path_ = pattern;
  }
  ~TemporaryDirectory() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  TemporaryDirectory(const TemporaryDirectory&) = delete;
  TemporaryDirectory& operator=(const TemporaryDirectory&) = delete;
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

// Why ccx stopped: its first "*ERROR" message (the cause; later ones follow from it) with its
// continuation lines up to the next blank line, else its last line before the closing banner (a
// rule of underscores and "Total CalculiX Time"); one line, trimmed.
std::string LastLine(const fs::path& log) {
  std::ifstream in(log);
  std::string line;
  std::string last;
  std::string error;
  bool in_error = false;
  while (std::getline(in, line)) {
    const std::size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos) {
      if (!error.empty()) break;
      continue;
    }
    const std::string text = line.substr(first, line.find_last_not_of(" \t\r") + 1 - first);
    in_error = in_error || text.rfind("*ERROR", 0) == 0;
    if (in_error) {
      error += (error.empty() ? "" : " ") + text;
    } else if (text[0] != '_' && text.find("Total CalculiX Time") == std::string::npos) {
      last = text;
    }
  }
  if (!error.empty()) return error;
  return last.empty() ? "no output" : last;
}

// posix_spawn_file_actions_t with its destroy, so that every exit path frees it.
struct SpawnActions {
  posix_spawn_file_actions_t actions;
  SpawnActions() { posix_spawn_file_actions_init(&actions); }
  ~SpawnActions() { posix_spawn_file_actions_destroy(&actions); }
  SpawnActions(const SpawnActions&) = delete;
  SpawnActions& operator=(const SpawnActions&) = delete;
};

// Starts `executable -i cantilever` in `directory`, stdin from /dev/null, stdout and stderr to
// `log`; no shell, so no quoting of paths. A relative executable path is made absolute first:
// the child resolves it after changing directory.
pid_t StartCcx(const std::string& executable, const fs::path& directory, const fs::path& log) {
  const std::string program =
      executable.find('/') == std::string::npos ? executable : fs::absolute(executable).string();
  SpawnActions spawn;
  posix_spawn_file_actions_addchdir_np(&spawn.actions, directory.c_str());
  posix_spawn_file_actions_addopen(&spawn.actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&spawn.actions, STDOUT_FILENO, log.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&spawn.actions, STDOUT_FILENO, STDERR_FILENO);
  std::string argument0 = program;
  std::string option = "-i";
  std::string job = kJob;
  char* argv[] = {argument0.data(), option.data(), job.data(), nullptr};
  pid_t pid = 0;
  const int error = posix_spawnp(&pid, program.c_str(), &spawn.actions, nullptr, argv, environ);
  if (error == ENOENT || error == EACCES) {
    throw std::runtime_error("CalculiX program '" + executable + "' not found or not executable (" +
                             std::strerror(error) + "); " + kInstallHint);
  }
  if (error != 0) {
    throw std::runtime_error("CalculiX program '" + executable +
                             "' cannot be started: " + std::strerror(error));
  }
  return pid;
}

// Waits for ccx; kills it after timeout_seconds (> 0). Returns waitpid's status.
int WaitForCcx(pid_t pid, double timeout_seconds, const fs::path& log) {
  const auto start = std::chrono::steady_clock::now();
  int status = 0;
  for (;;) {
    const pid_t done = waitpid(pid, &status, timeout_seconds > 0.0 ? WNOHANG : 0);
    if (done == pid) return status;
    if (done < 0 && errno != EINTR) {
      throw std::runtime_error(std::string("CalculiX cantilever: waiting for ccx failed: ") +
                               std::strerror(errno));
    }
    const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - start;
    if (timeout_seconds > 0.0 && elapsed.count() > timeout_seconds) {
      kill(pid, SIGKILL);
      while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
      }
      throw std::runtime_error("CalculiX did not finish within " + Str(timeout_seconds) +
                               " s (last output: " + LastLine(log) + ")");
    }
    // Polling only with a timeout; the poll's lag is nothing beside a solve.
    if (done == 0) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

void CheckExitStatus(int status, const fs::path& log) {
  if (WIFSIGNALED(status)) {
    throw std::runtime_error("CalculiX was ended by signal " + std::to_string(WTERMSIG(status)) +
                             ": " + LastLine(log));
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    throw std::runtime_error("CalculiX failed (exit code " + std::to_string(WEXITSTATUS(status)) +
                             "): " + LastLine(log));
  }
}

// Fortran's E format drops the "E" of a three-digit exponent ("1.234567-100"), which strtod
// alone would read as 1.234567.
bool ParseFortranDouble(const std::string& token, double* value) {
  const char* begin = token.c_str();
  char* end = nullptr;
  const double mantissa = std::strtod(begin, &end);
  if (end == begin) return false;
  if (*end == '\0') {
    *value = mantissa;
    return true;
  }
  if (*end != '+' && *end != '-') return false;
  char* exponent_end = nullptr;
  const long exponent = std::strtol(end, &exponent_end, 10);
  if (*exponent_end != '\0') return false;
  *value = mantissa * std::pow(10.0, static_cast<double>(exponent));
  return true;
}

// One "node ux uy uz" line of a displacement block; false for any other line.
bool ParseDisplacementLine(const std::string& line, long* node, double* uz) {
  std::istringstream fields(line);
  std::string tokens[4];
  std::string extra;
  if (!(fields >> tokens[0] >> tokens[1] >> tokens[2] >> tokens[3]) || (fields >> extra)) {
    return false;
  }
  char* end = nullptr;
  *node = std::strtol(tokens[0].c_str(), &end, 10);
  double ignored = 0.0;
  return *end == '\0' && ParseFortranDouble(tokens[1], &ignored) &&
         ParseFortranDouble(tokens[2], &ignored) && ParseFortranDouble(tokens[3], uz);
}

// u_z of every node, from the last "displacements (vx,vy,vz) for set NALL" block of the .dat file.
std::vector<double> ReadVerticalDisplacements(const fs::path& dat, long nodes,
                                              const fs::path& log) {
  std::ifstream in(dat);
  std::vector<double> uz(nodes, 0.0);
  std::vector<bool> seen(nodes, false);
  bool in_block = false;
  std::string line;
  while (std::getline(in, line)) {
    if (line.find("displacements") != std::string::npos && line.find("NALL") != std::string::npos) {
      in_block = true;
      continue;
    }
    if (!in_block || line.find_first_not_of(" \t\r") == std::string::npos) continue;
    long node = 0;
    double value = 0.0;
    in_block = ParseDisplacementLine(line, &node, &value);
    if (in_block && node >= 1 && node <= nodes) {
      uz[node - 1] = value;
      seen[node - 1] = true;
    }
  }
  for (long n = 0; n < nodes; ++n) {
    if (!seen[n]) {
      throw std::runtime_error("CalculiX wrote no displacement for node " + std::to_string(n + 1) +
                               " in " + dat.filename().string() +
                               " (last output: " + LastLine(log) + ")");
    }
  }
  return uz;
}

// Mean -u_z per station x_i = length i / nx.
CalculixCantileverResult Profile(const CalculixCantilever& box, const std::vector<double>& uz) {
  CalculixCantileverResult result;
  const int per_station = (box.elements_y + 1) * (box.elements_z + 1);
  for (int i = 0; i <= box.elements_x; ++i) {
    double sum = 0.0;
    for (int k = 0; k <= box.elements_z; ++k) {
      for (int j = 0; j <= box.elements_y; ++j) sum -= uz[NodeNumber(box, i, j, k) - 1];
    }
    result.profile.push_back({box.length * i / box.elements_x, sum / per_station});
  }
  result.end_face_deflection = result.profile.back().deflection;
  return result;
}

}  // namespace

std::string CalculixCantileverDeck(const CalculixCantilever& box) {
  Validate(box);
  std::ostringstream deck;
  // CalculiX reads at most 20 characters per field: 12 digits keep "-1.23456789012e-100" within
  // it (and the grid's coordinates to 1e-12 of the box).
  deck.precision(12);
  deck << "** msm_sim cantilever reference: clamped at x = 0, loaded in -z at x = L\n"
       << "*HEADING\nmsm_sim cantilever " << box.length << " x " << box.width << " x " << box.height
       << " m, C3D8I " << box.elements_x << " x " << box.elements_y << " x " << box.elements_z
       << "\n";
  WriteNodes(box, deck);
  WriteElements(box, deck);
  deck << "*MATERIAL, NAME=BOX\n*ELASTIC\n"
       << box.youngs << ", " << box.poisson << "\n"
       << "*SOLID SECTION, ELSET=EALL, MATERIAL=BOX\n";
  WriteClamp(box, deck);
  deck << "*STEP\n*STATIC\n";
  WriteLoads(box, deck);
  deck << "*NODE PRINT, NSET=NALL\nU\n*END STEP\n";
  return deck.str();
}

CalculixCantileverResult RunCalculixCantilever(const CalculixCantilever& box) {
  const std::string deck = CalculixCantileverDeck(box);
  const TemporaryDirectory directory;
  const fs::path input = directory.path() / (std::string(kJob) + ".inp");
  const fs::path log = directory.path() / "ccx.log";
  {
    std::ofstream out(input);
    out << deck;
    if (!out.flush()) {
      throw std::runtime_error("CalculiX cantilever: cannot write " + input.string());
    }
  }
  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = StartCcx(box.executable, directory.path(), log);
  CheckExitStatus(WaitForCcx(pid, box.timeout_seconds, log), log);
  const std::chrono::duration<double> seconds = std::chrono::steady_clock::now() - start;
  CalculixCantileverResult result =
      Profile(box, ReadVerticalDisplacements(directory.path() / (std::string(kJob) + ".dat"),
                                             NodeCount(box), log));
  result.seconds = seconds.count();
  return result;
}

}  // namespace msm_sim::core
