// Checks on the files a tool is given, before it opens or allocates for them.
#pragma once

#include <cstdint>
#include <string>

namespace fov {

// Why `path` cannot be read as an input file, or "" when it can: it does not exist, is a
// directory, or is not a regular file (a FIFO, device or socket, whose open or read may
// block or never end). Symbolic links are followed.
std::string input_file_problem(const std::string& path);

// The machine's physical memory in bytes (0 when unknown): what no single allocation a
// file asks for may exceed.
uint64_t physical_memory_bytes();

// "" when `bytes` (what `what` needs) fits in physical memory, else why not, in one line.
std::string memory_problem(uint64_t bytes, const std::string& what);

}  // namespace fov
