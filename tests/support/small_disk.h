// A small disk for a test that fills one: a tmpfs of `size` mounted at `dir` (made), when the
// test runs as root (as CI does) and the system lets it; unmounted and removed at the end.
#pragma once

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <string>

namespace saccade::testing {

class SmallDisk {
 public:
  SmallDisk(std::string dir, const std::string& size) : dir_(std::move(dir)) {
    if (geteuid() != 0) return;
    std::filesystem::create_directories(dir_);
    mounted_ =
        std::system(
            ("mount -t tmpfs -o size=" + size + " tmpfs " + dir_ + " 2>/dev/null").c_str()) == 0;
  }
  ~SmallDisk() {
    if (mounted_) (void)std::system(("umount " + dir_).c_str());
    std::error_code ec;
    std::filesystem::remove(dir_, ec);
  }
  SmallDisk(const SmallDisk&) = delete;
  SmallDisk& operator=(const SmallDisk&) = delete;

  /// False when not root or the mount failed: the test skips.
  bool mounted() const { return mounted_; }
  const std::string& dir() const { return dir_; }
  /// Leaves `free_kb` of room: the rest taken by a file of zeros (all of it with 0).
  void Fill(int free_kb) const {
    (void)std::system(("dd if=/dev/zero of=" + dir_ + "/filler bs=1k 2>/dev/null").c_str());
    if (free_kb > 0)
      std::filesystem::resize_file(dir_ + "/filler",
                                   std::filesystem::file_size(dir_ + "/filler") - 1024u * free_kb);
  }

 private:
  std::string dir_;
  bool mounted_ = false;
};

}  // namespace saccade::testing
