#pragma once
// One expensive fixture (a quick study and its rendered report) for every test process of a
// suite. gtest_discover_tests runs each test in its own process, so SetUpTestSuite would build it
// once per test; this builds it once per build tree and key, under a lock, and the others reuse it.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace clearshape::testing {

/// The fixture folder `name` in the build tree's test cache, holding what `build` wrote there.
/// `build(folder)` runs (under an exclusive lock on `name`.lock, into a fresh temporary folder that
/// is then renamed) unless the folder exists with the same `key`; it returns false on failure,
/// and the folder is then not kept. Every process gets the same folder. Throws on I/O errors.
std::filesystem::path shared_fixture(const std::string& name, const std::string& key,
                                     const std::function<bool(const std::filesystem::path&)>& build);

/// A key that changes whenever one of `files` (or a file under one of them) changes: their
/// paths, sizes and modification times.
std::string files_key(const std::vector<std::filesystem::path>& files);

}  // namespace clearshape::testing
