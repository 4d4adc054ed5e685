// Crash safety: bakes and renders killed with SIGKILL at random instants leave either the complete
// earlier output or the complete new one, and the next run leaves no trace of the killed one.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>

#include <nlohmann/json.hpp>

#include "ndfmip/io.h"
#include "test_support.h"

extern char** environ;

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace ndfmip::test {
namespace {

constexpr int kKillsPerCommand = 12; // a bake and a render: 24 kills in all

// Starts the CLI with `args`, its output thrown away; returns its pid.
pid_t startCli(const std::vector<std::string>& args) {
    std::vector<std::string> all = {NDFMIP_CLI_PATH};
    all.insert(all.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& a : all) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
    pid_t pid = -1;
    const int err = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    return err == 0 ? pid : -1;
}

// Waits for `pid`; its exit status, or 128 + the signal that ended it.
int waitFor(pid_t pid) {
    int status = 0;
    ::waitpid(pid, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

// Runs the command to its end: its duration, after checking that it succeeded.
Clock::duration runToEnd(const std::vector<std::string>& args) {
    const auto start = Clock::now();
    const pid_t pid = startCli(args);
    EXPECT_GT(pid, 0);
    EXPECT_EQ(waitFor(pid), 0) << args.front();
    return Clock::now() - start;
}

Image bumpyMap(int size) {
    Image map(size, size, 3);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            setNormal(map, x, y, 0.4f * std::sin(0.3f * float(x)), 0.3f * std::cos(0.2f * float(y)),
                      1.f);
            for (int c = 0; c < 3; ++c) map.at(x, y)[c] = 0.5f * (map.at(x, y)[c] + 1.f);
        }
    return map;
}

// Runs `command` kKillsPerCommand times over the earlier output, each time killed after a random
// delay up to 1.3 times its full duration; `isOldOrNew` checks what the kill left, then the same
// command runs to its end and must leave the new output and no leftovers under `root`.
void killRepeatedly(const fs::path& root, const std::vector<std::string>& command,
                    const std::function<void()>& restoreOld,
                    const std::function<void(const std::string&)>& isOldOrNew,
                    const std::function<void()>& isNew) {
    restoreOld();
    const Clock::duration full = runToEnd(command);
    std::mt19937 random(20240917);
    int killedWhileRunning = 0;
    for (int i = 0; i < kKillsPerCommand; ++i) {
        restoreOld();
        const auto delay = std::chrono::duration_cast<Clock::duration>(
            full * std::uniform_real_distribution<double>(0.0, 1.3)(random));
        const pid_t pid = startCli(command);
        ASSERT_GT(pid, 0);
        std::this_thread::sleep_for(delay);
        ::kill(pid, SIGKILL);
        const int status = waitFor(pid);
        killedWhileRunning += status == 128 + SIGKILL;
        const std::string trace = "kill " + std::to_string(i) + " after " +
                                  std::to_string(std::chrono::duration<double>(delay).count()) +
                                  " s, status " + std::to_string(status);
        isOldOrNew(trace);
        runToEnd(command);
        SCOPED_TRACE(trace);
        isNew();
        EXPECT_EQ(leftovers(root), std::vector<std::string>{}) << "the next run did not clean up";
    }
    EXPECT_GE(killedWhileRunning, kKillsPerCommand / 4) << "too few kills landed while it ran";
}

TEST(CrashSafety, KilledBakesLeaveTheOldOrTheNewBake) {
    TempDir tmp("crash-bake");
    const std::string map = tmp.file("map.png");
    ASSERT_TRUE(savePng(map, bumpyMap(384), 16));
    const fs::path dir = tmp.path / "bake", refs = tmp.path / "refs";
    fs::create_directory(refs);
    // The earlier bake (naive) and the new one (toksvig with engine exports), made once.
    runToEnd({"bake", map, "-q", "--method", "naive", "-o", (refs / "old").string()});
    const std::vector<std::string> command = {"bake",     map,     "-q", "--method",  "toksvig",
                                              "--export", "png16", "-o", dir.string()};
    runToEnd({"bake", map, "-q", "--method", "toksvig", "--export", "png16", "-o",
              (refs / "new").string()});
    const auto oldBake = snapshot(refs / "old"), newBake = snapshot(refs / "new");
    ASSERT_NE(oldBake, newBake);
    killRepeatedly(
        tmp.path, command,
        [&] {
            fs::remove_all(dir);
            fs::copy(refs / "old", dir, fs::copy_options::recursive);
        },
        [&](const std::string& trace) {
            const auto now = snapshot(dir);
            EXPECT_TRUE(now == oldBake || now == newBake)
                << trace << ": the bake folder is neither the old bake nor the new one ("
                << now.size() << " files)";
        },
        [&] { EXPECT_EQ(snapshot(dir), newBake); });
}

TEST(CrashSafety, KilledRendersLeaveTheOldOrTheNewImages) {
    TempDir tmp("crash-render");
    ASSERT_TRUE(savePng(tmp.file("map.png"), bumpyMap(128), 16));
    const nlohmann::json scene = {
        {"camera",
         {{"type", "perspective"},
          {"eye", {0, -2, 1.5}},
          {"target", {0, 0, 0}},
          {"up", {0, 0, 1}},
          {"width", 320},
          {"height", 240}}},
        {"object", {{"type", "plane"}, {"size", {4, 4}}, {"tiling", {4, 4}}}},
        {"lights", {{{"type", "directional"}, {"direction", {0.3, -0.5, 1}}}}},
        {"material", {{"brdf", "blinnphong"}, {"exponent", 64}}},
        {"normal_map", "map.png"}};
    writeBytes(tmp.path / "scene.json", scene.dump());
    const std::string sceneFile = tmp.file("scene.json");
    const fs::path refs = tmp.path / "refs";
    fs::create_directory(refs);
    runToEnd({"render", sceneFile, "-q", "--method", "naive", "-o", (refs / "old.exr").string()});
    runToEnd({"render", sceneFile, "-q", "--method", "toksvig", "--spp", "4", "-o",
              (refs / "new.exr").string()});
    const std::map<std::string, std::string> oldFiles = {{"exr", fileBytes(refs / "old.exr")},
                                                         {"png", fileBytes(refs / "old.png")}};
    const std::map<std::string, std::string> newFiles = {{"exr", fileBytes(refs / "new.exr")},
                                                         {"png", fileBytes(refs / "new.png")}};
    ASSERT_NE(oldFiles, newFiles);
    const fs::path out = tmp.path / "out";
    const std::vector<std::string> command = {"render",   sceneFile, "-q",
                                              "--method", "toksvig", "--spp",
                                              "4",        "-o",      out.string() + ".exr"};
    killRepeatedly(
        tmp.path, command,
        [&] {
            for (const char* ext : {"exr", "png"})
                writeBytes(out.string() + "." + ext, oldFiles.at(ext));
        },
        [&](const std::string& trace) {
            // Each file is replaced atomically on its own: old or new, never a mixture.
            for (const char* ext : {"exr", "png"}) {
                const std::string now = fileBytes(out.string() + "." + ext);
                EXPECT_TRUE(now == oldFiles.at(ext) || now == newFiles.at(ext))
                    << trace << ": out." << ext << " is neither the old file nor the new one";
            }
        },
        [&] {
            for (const char* ext : {"exr", "png"})
                EXPECT_EQ(fileBytes(out.string() + "." + ext), newFiles.at(ext)) << ext;
        });
}

} // namespace
} // namespace ndfmip::test
