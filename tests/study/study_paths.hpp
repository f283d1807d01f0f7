#pragma once
// Where the study tests find the committed protocols: studies_path() lives in support/paths.hpp.
#include <filesystem>

#include "support/paths.hpp"
