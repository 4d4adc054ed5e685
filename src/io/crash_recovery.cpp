// Leftovers of killed runs: telling stale ones from those of running processes, removing or
// restoring them, and the folder swap that keeps a bake whole at every instant.
#include "io/crash_recovery.h"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <fcntl.h>
#include <signal.h>
#include <stdio.h> // renameat2, RENAME_EXCHANGE (glibc 2.28)
#include <sys/stat.h>
#include <unistd.h>

#include "ndfmip/paths.h"

namespace fs = std::filesystem;

namespace ndfmip {
namespace {

// Seconds since the epoch at which the system booted, or -1.
int64_t bootTime() {
    std::ifstream stat("/proc/stat");
    std::string line;
    while (std::getline(stat, line))
        if (line.rfind("btime ", 0) == 0) return std::strtoll(line.c_str() + 6, nullptr, 10);
    return -1;
}

// Seconds since the epoch at which process `pid` started, or -1 when /proc cannot say.
int64_t processStartTime(long pid) {
    std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
    std::string text;
    std::getline(stat, text);
    // The command name (field 2) is in parentheses and may hold spaces: count after the last
    // ')'. Field 22 is the start time in clock ticks after boot.
    const size_t close = text.rfind(')');
    if (close == std::string::npos) return -1;
    std::istringstream fields(text.substr(close + 1));
    std::string field;
    for (int i = 3; i <= 22; ++i)
        if (!(fields >> field)) return -1;
    const long ticks = ::sysconf(_SC_CLK_TCK);
    const int64_t boot = bootTime();
    if (ticks <= 0 || boot < 0) return -1;
    return boot + int64_t(std::strtoull(field.c_str(), nullptr, 10) / uint64_t(ticks));
}

int64_t modifiedSeconds(const fs::path& path) {
    struct stat info {};
    return ::lstat(path.c_str(), &info) == 0 ? int64_t(info.st_mtime) : 0;
}

// The PID in NAME = PREFIX + digits + "-" + anything (a writer's tag), or, unless `suffix`,
// PREFIX + digits alone (as earlier versions named their folders); else -1.
long pidAfter(const std::string& name, const std::string& prefix, bool suffix) {
    if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0) return -1;
    size_t end = prefix.size();
    while (end < name.size() && end - prefix.size() < 10 && name[end] >= '0' && name[end] <= '9')
        ++end;
    if (end == prefix.size()) return -1;
    const bool tagged = end < name.size() && name[end] == '-';
    if (!tagged && (suffix || end != name.size())) return -1;
    return std::stol(name.substr(prefix.size(), end - prefix.size()));
}

void syncFolder(const fs::path& folder) {
    int fd = ::open(folder.empty() ? "." : folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) return;
    ::fsync(fd);
    ::close(fd);
}

fs::path parentOf(const fs::path& path) {
    return path.has_parent_path() ? path.parent_path() : fs::path(".");
}

Status cannotReplace(const fs::path& dir, int err) {
    return Status::failure(dir.string() + ": cannot replace (" + std::strerror(err) + ")");
}

} // namespace

std::string writerTag() {
    static std::atomic<unsigned long long> made{0};
    return std::to_string(::getpid()) + "-" + std::to_string(long(::gettid())) + "-" +
           std::to_string(++made);
}

bool writerMayBeAlive(long pid, int64_t modified) {
    if (pid <= 0) return false;
    if (::kill(pid_t(pid), 0) != 0 && errno == ESRCH) return false;
    // The number is taken; by the same process only if that one started before the leftover
    // was last written (a second of slack for the clocks' rounding).
    const int64_t started = processStartTime(pid);
    return started < 0 || started <= modified + 1;
}

void recoverFolderLeftovers(const fs::path& dir) {
    const std::string base = dir.filename().string();
    std::vector<std::pair<int64_t, fs::path>> partial, old;
    std::error_code ec;
    for (fs::directory_iterator it(parentOf(dir), ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        const bool isOld = pidAfter(name, base + ".old-", false) > 0;
        const long pid = isOld ? pidAfter(name, base + ".old-", false)
                               : pidAfter(name, base + ".partial-", false);
        if (pid <= 0) continue;
        const int64_t modified = modifiedSeconds(it->path());
        if (writerMayBeAlive(pid, modified)) continue;
        (isOld ? old : partial).emplace_back(modified, it->path());
    }
    std::sort(old.rbegin(), old.rend()); // newest first
    struct stat info {};
    if (!old.empty() && ::lstat(dir.c_str(), &info) != 0 && errno == ENOENT) {
        // Killed between its two renames: the earlier folder goes back where it was.
        fs::rename(old.front().second, dir, ec);
        if (!ec) old.erase(old.begin());
        syncFolder(parentOf(dir));
    }
    for (const auto& group : {partial, old})
        for (const auto& [modified, path] : group) fs::remove_all(path, ec);
}

void removeStaleTemporaries(const fs::path& path) {
    const std::string prefix = path.filename().string() + ".tmp-";
    std::error_code ec;
    for (fs::directory_iterator it(parentOf(path), ec), end; !ec && it != end; it.increment(ec)) {
        const long pid = pidAfter(it->path().filename().string(), prefix, true);
        if (pid <= 0 || writerMayBeAlive(pid, modifiedSeconds(it->path()))) continue;
        if (!it->is_directory(ec)) fs::remove(it->path(), ec);
    }
}

Status replaceFolder(const fs::path& staging, const fs::path& dir, bool exchange) {
    // The files' directory entries reach the disk before the folder is published.
    syncFolder(staging);
    const fs::path parent = parentOf(dir);
    struct stat info {};
    if (::lstat(dir.c_str(), &info) != 0) {
        if (errno != ENOENT) return cannotReplace(dir, errno);
        if (::rename(staging.c_str(), dir.c_str()) == 0) {
            syncFolder(parent);
            return Status::success();
        }
        // Another writer of dir (a thread of this process, say) put its folder there first:
        // replace that one as any earlier folder.
        if (errno != EEXIST && errno != ENOTEMPTY)
            return Status::failure(dir.string() + ": cannot create (" + std::strerror(errno) + ")");
    }
    if (exchange) {
        if (::renameat2(AT_FDCWD, staging.c_str(), AT_FDCWD, dir.c_str(), RENAME_EXCHANGE) == 0) {
            syncFolder(parent);
            std::error_code ec;
            fs::remove_all(staging, ec); // now the earlier folder
            return Status::success();
        }
        if (errno != EINVAL && errno != ENOSYS && errno != EOPNOTSUPP && errno != ENOTSUP)
            return cannotReplace(dir, errno);
    }
    // No atomic exchange here: set the earlier folder aside, then move the new one in.
    const fs::path old = dir.string() + ".old-" + writerTag();
    if (::rename(dir.c_str(), old.c_str()) != 0) return cannotReplace(dir, errno);
    if (::rename(staging.c_str(), dir.c_str()) != 0) {
        const int err = errno;
        ::rename(old.c_str(), dir.c_str());
        return cannotReplace(dir, err);
    }
    syncFolder(parent);
    std::error_code ec;
    fs::remove_all(old, ec);
    return Status::success();
}

fs::path folderPath(const std::string& name) {
    fs::path dir = fs::path(name).lexically_normal();
    if (dir.filename().empty()) dir = dir.parent_path();
    return dir;
}

namespace {

// replaceable(dir), run again when another writer swapped its own folder in while dir was being
// read (bakes into one folder at once): the old manifest against the new folder's files is not a
// stranger's work. A refusal stands once dir was one and the same folder throughout the check.
Status checkReplaceableFolder(const fs::path& dir,
                              const std::function<Status(const fs::path& dir)>& replaceable) {
    for (int attempt = 1;; ++attempt) {
        struct stat before = {};
        if (::stat(dir.c_str(), &before) != 0) return Status::success(); // nothing to replace
        Status s = replaceable(dir);
        if (s || attempt == 8) return s;
        struct stat after = {};
        if (::stat(dir.c_str(), &after) == 0 && after.st_ino == before.st_ino &&
            after.st_dev == before.st_dev)
            return s;
    }
}

} // namespace

Status writeFolderWhole(const std::string& name,
                        const std::function<Status(const fs::path& dir)>& replaceable,
                        const std::function<Status(const fs::path& staging)>& fill) {
    if (Status s = checkUntrustedPath(name); !s) return s;
    const fs::path dir = folderPath(name);
    std::error_code ec;
    // A link is refused, not replaced by the new folder (which would cut it from what it points
    // to) nor followed (the staging folder would be made beside the link, not its target).
    if (fs::is_symlink(fs::symlink_status(dir, ec)))
        return Status::failure(name + ": is a symbolic link (to " +
                               fs::read_symlink(dir, ec).string() +
                               "); give the folder itself to replace it");
    const fs::path parent = dir.has_parent_path() ? dir.parent_path() : fs::path(".");
    if (!fs::is_directory(parent, ec))
        return Status::failure(name + ": parent folder " + parent.string() +
                               (fs::exists(parent, ec) ? " is not a folder" : " does not exist"));
    recoverFolderLeftovers(dir);
    if (Status s = checkReplaceableFolder(dir, replaceable); !s) return s;
    // A name of this writer's own: threads writing beside one another never share one.
    const fs::path staging = dir.string() + ".partial-" + writerTag();
    if (!fs::create_directory(staging, ec))
        return Status::failure(name + ": cannot write (" +
                               (ec ? ec.message() : std::string("staging folder exists")) + ")");
    Status s = fill(staging);
    if (s) s = checkReplaceableFolder(dir, replaceable);
    if (s) s = replaceFolder(staging, dir);
    if (!s) fs::remove_all(staging, ec);
    return s;
}

} // namespace ndfmip
