// Regular files only, read with a bound; JSON nesting measured before parsing.
#include "io/input_file.h"

#include <algorithm>
#include <cerrno>
#include <cstring>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "ndfmip/limits.h"
#include "ndfmip/paths.h"

namespace ndfmip {
namespace {

Error cannotRead(const std::string& path, const std::string& why) {
    return Error{path + ": cannot read: " + why};
}

const char* fileKind(mode_t mode) {
    if (S_ISFIFO(mode)) return "a FIFO";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISSOCK(mode)) return "a socket";
    return "not a plain file";
}

} // namespace

Result<int> openRegularFile(const std::string& path) {
    if (Status s = checkUntrustedPath(path); !s) return Error{s.error};
    // O_NONBLOCK: opening a FIFO without a writer would otherwise wait forever. The type is
    // checked on the open descriptor, so the file cannot be swapped between check and read.
    int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
    if (fd < 0) return cannotRead(path, std::strerror(errno));
    struct stat info {};
    if (::fstat(fd, &info) != 0) {
        int err = errno;
        ::close(fd);
        return cannotRead(path, std::strerror(err));
    }
    if (!S_ISREG(info.st_mode)) {
        ::close(fd);
        if (S_ISDIR(info.st_mode)) return cannotRead(path, "is a directory");
        return cannotRead(path, std::string("not a regular file (") + fileKind(info.st_mode) + ")");
    }
    ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
    return fd;
}

Result<std::string> readRegularFile(const std::string& path, int64_t maxBytes) {
    Result<int> fd = openRegularFile(path);
    if (!fd) return fd.error();
    struct stat info {};
    ::fstat(fd.value(), &info);
    auto tooLarge = [&](int64_t size) {
        return cannotRead(path, byteSize(size) + ", above the limit of " + byteSize(maxBytes) +
                                    " for this kind of file");
    };
    if (info.st_size > maxBytes) {
        ::close(fd.value());
        return tooLarge(info.st_size);
    }
    std::string bytes;
    bytes.resize(size_t(info.st_size));
    size_t done = 0;
    // A file that grows while it is read is read up to the limit, never further.
    while (true) {
        if (done == bytes.size()) {
            if (int64_t(bytes.size()) > maxBytes) {
                ::close(fd.value());
                return tooLarge(int64_t(bytes.size()));
            }
            bytes.resize(std::min<size_t>(bytes.size() + (1 << 16), size_t(maxBytes) + 1));
        }
        ssize_t n = ::read(fd.value(), bytes.data() + done, bytes.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) {
            int err = errno;
            ::close(fd.value());
            return cannotRead(path, std::strerror(err));
        }
        if (n == 0) break;
        done += size_t(n);
    }
    ::close(fd.value());
    bytes.resize(done);
    return bytes;
}

std::string jsonNestingProblem(std::string_view text, int maxDepth) {
    int depth = 0, line = 1;
    bool inString = false;
    for (size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (c == '\n') ++line;
        if (inString) {
            if (c == '\\')
                ++i; // the escaped character cannot end the string
            else if (c == '"')
                inString = false;
            continue;
        }
        if (c == '"')
            inString = true;
        else if (c == '[' || c == '{') {
            if (++depth > maxDepth)
                return "nested deeper than " + std::to_string(maxDepth) + " levels at line " +
                       std::to_string(line);
        } else if ((c == ']' || c == '}') && depth > 0)
            --depth;
    }
    return "";
}

std::string oneLine(std::string text) {
    for (char& c : text)
        if (static_cast<unsigned char>(c) < 0x20) c = ' ';
    while (!text.empty() && (text.back() == ' ' || text.back() == '.')) text.pop_back();
    return text;
}

Error fileError(const std::string& path, const std::string& problem) {
    return Error{path + ": " + oneLine(problem)};
}

} // namespace ndfmip
