#include "dc/bench/render_frame.hpp"

#include <cerrno>
#include <cstdlib>
#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include "dc/engine/scene.hpp"
#include "dc/core/install_paths.hpp"

namespace dc::bench {
namespace fs = std::filesystem;
namespace {

std::string python_interpreter() {
  if (const char* py = std::getenv("DC_BENCH_PYTHON"); py && *py) return py;
  return fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
}

std::string renderer_script() { return data_path("bench/plots/render_trajectory.py").string(); }

}  // namespace

std::string renderer_command() {
  // Appended piece by piece: the one-expression form trips GCC 12's -Wrestrict false positive.
  std::string cmd = "'";
  cmd += python_interpreter();
  cmd += "' '";
  cmd += renderer_script();
  cmd += "'";
  return cmd;
}

int run_renderer(const std::vector<std::string>& args, const std::string& log, const std::string& cwd) {
  std::vector<std::string> words{python_interpreter(), renderer_script()};
  words.insert(words.end(), args.begin(), args.end());
  if (!log.empty()) words.push_back("--no-progress");
  std::vector<char*> argv;
  for (auto& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  const pid_t pid = fork();
  if (pid < 0) return 127;
  if (pid == 0) {
    if (!log.empty()) {
      const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      if (fd >= 0) {
        dup2(fd, STDOUT_FILENO);
        dup2(fd, STDERR_FILENO);
        close(fd);
      }
    }
    if (!cwd.empty() && chdir(cwd.c_str()) != 0) _exit(127);
    execvp(argv[0], argv.data());
    _exit(127);
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return 127;
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

std::string reference_frame_markdown(const BenchResults& r, const fs::path& dir, std::vector<std::string>& files) {
  if (!r.reference || r.reference->steps() < 1) return "";
  const fs::path h5 = dir / "reference.h5", png = dir / "reference_frame.png";
  r.reference->write(h5.string(), r.reference_scene, "oracle");
  files.push_back(h5.string());
  std::error_code ec;
  fs::remove(png, ec);
  const int frame = r.reference->steps() - 1;  // the last step: the settled pile and its forces
  // Run inside `dir` with bare names: `dir` is a staging folder renamed when the report is
  // complete, so render.log names the report's files, not the folder that is gone by then.
  const int code = run_renderer({h5.filename().string(), "--frame", std::to_string(frame), "--out",
                                 png.filename().string()},
                                (dir / "render.log").string(), dir.string());
  std::string md = "## Reference trajectory\n\n";
  if (code == 0 && fs::exists(png)) {
    files.push_back(png.string());
    md += "![reference_frame.png](reference_frame.png)\n\nState " + std::to_string(frame) + " of the reference "
          "trajectory of seed " + std::to_string(r.options.seeds.front()) + " (advanced with λ*) and the forces "
          "solved in that step (segments along the normal, length and colour ∝ λ_n). The whole trajectory is "
          "`reference.h5`: `deepcontact render reference.h5 --out reference.gif` animates it.\n\n";
  } else {
    md += "*(reference_frame.png missing: the renderer exited with " + std::to_string(code) +
          " — see render.log; the trajectory is reference.h5)*\n\n";
  }
  return md;
}

}  // namespace dc::bench
