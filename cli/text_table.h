#pragma once

#include <string>
#include <vector>

namespace omnishadow::cli {

// Rows of cells, printed as columns.
using TextTable = std::vector<std::vector<std::string>>;

// Each column as wide as its widest cell, one space between columns, every line indented by two
// spaces and without trailing spaces; one "\n"-terminated line per row.
std::string formatTable(const TextTable& rows);

// formatTable() on stdout.
void printTable(const TextTable& rows);

}  // namespace omnishadow::cli
