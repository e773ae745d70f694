#include "io/small_file.h"

#include <fstream>
#include <iterator>

#include "rtd/error.h"

namespace rtd {

namespace fs = std::filesystem;

std::string readSmallFile(const fs::path& path, std::uintmax_t maxBytes, const std::string& what) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw Error(what + ": the file does not exist");
  if (!fs::is_regular_file(path, ec)) throw Error(what + ": not a regular file");
  const std::uintmax_t bytes = fs::file_size(path, ec);
  if (ec) throw Error(what + ": cannot read its size (" + ec.message() + ")");
  if (bytes > maxBytes)
    throw Error(what + ": " + std::to_string(bytes) + " bytes, more than the " + std::to_string(maxBytes >> 20) +
                " MiB such a file may have");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(what + ": cannot open the file");
  std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad() || data.size() != bytes) throw Error(what + ": cannot read the file");
  return data;
}

}  // namespace rtd
