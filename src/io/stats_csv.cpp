// StatsCsv: per-step statistics table (see stats_csv.hpp).
#include "io/stats_csv.hpp"

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "io/collective_error.hpp"

namespace dipc {

StatsCsv::StatsCsv(const std::string& path, std::vector<std::string> columns, MPI_Comm comm, long keep_through_step)
    : path_(path), columns_(std::move(columns)) {
  if (columns_.empty()) throw std::invalid_argument("StatsCsv '" + path_ + "': no columns");
  for (const std::string& c : columns_) {
    if (c.find_first_of(",\"\r\n") != std::string::npos) {
      throw std::invalid_argument("StatsCsv '" + path_ + "': column name \"" + c +
                                  "\" would need CSV quoting (comma, quote or line break)");
    }
  }
  int mpi_initialized = 0;
  MPI_Initialized(&mpi_initialized);
  if (mpi_initialized) {
    comm_ = comm;
    int rank = 0;
    MPI_Comm_rank(comm_, &rank);
    writes_ = rank == 0;
  }

  std::string error;
  if (writes_) {
    const std::filesystem::path parent = std::filesystem::path(path_).parent_path();
    std::error_code ec;
    if (!parent.empty()) std::filesystem::create_directories(parent, ec);
    std::string header;
    for (const std::string& c : columns_) header += (header.empty() ? "" : ",") + c;
    header += "\n";
    if (keep_through_step >= 0 && std::filesystem::exists(path_)) {
      error = continue_table(header, keep_through_step);
    } else if (file_.reset(std::fopen(path_.c_str(), "w")), !file_) {
      error = "cannot create '" + path_ + "': " + std::strerror(errno);
    } else {
      if (std::fputs(header.c_str(), file_.get()) < 0 || std::fflush(file_.get()) != 0) {
        error = "cannot write '" + path_ + "': " + std::strerror(errno);
      }
    }
  }
  check(error);
}

std::string StatsCsv::continue_table(const std::string& header, long keep_through_step) {
  std::ifstream in(path_);
  std::string line, kept;
  if (!std::getline(in, line) || line + "\n" != header)
    return "cannot continue '" + path_ + "': its header is not this run's (" + line + ")";
  kept = header;
  // A line cut short by a killed run has no line break at the end; it is dropped with the
  // rows after the checkpoint.
  while (std::getline(in, line) && !in.eof()) {
    char* end = nullptr;
    const double step = std::strtod(line.c_str(), &end);
    if (end == line.c_str() || step > static_cast<double>(keep_through_step)) break;
    kept += line + "\n";
  }
  in.close();
  const std::string temporary = path_ + ".tmp";
  {
    std::ofstream out(temporary, std::ios::trunc);
    out << kept;
    out.close();
    if (!out) return "cannot write '" + temporary + "'";
  }
  std::error_code ec;
  std::filesystem::rename(temporary, path_, ec);
  if (ec) return "cannot rename '" + temporary + "' to '" + path_ + "': " + ec.message();
  file_.reset(std::fopen(path_.c_str(), "a"));
  if (!file_) return "cannot open '" + path_ + "' to append: " + std::strerror(errno);
  return {};
}

StatsCsv::Cell::Cell(double value) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", value);
  csv_ = buf;
}

StatsCsv::Cell::Cell(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) {
    csv_ = text;
    return;
  }
  csv_ = "\"";
  for (char c : text) csv_ += c == '"' ? std::string("\"\"") : std::string(1, c);
  csv_ += "\"";
}

void StatsCsv::row(const std::vector<Cell>& values) {
  if (values.size() != columns_.size()) {
    throw std::invalid_argument("StatsCsv '" + path_ + "': row has " + std::to_string(values.size()) + " values for " +
                                std::to_string(columns_.size()) + " columns");
  }
  std::string error;
  if (writes_) {
    bool ok = true;
    for (std::size_t i = 0; i < values.size(); ++i) {
      ok = ok && (i == 0 || std::fputc(',', file_.get()) != EOF) &&
           std::fputs(values[i].csv().c_str(), file_.get()) >= 0;
    }
    ok = ok && std::fputc('\n', file_.get()) != EOF && std::fflush(file_.get()) == 0;
    if (!ok) error = "cannot write '" + path_ + "': " + std::strerror(errno);
  }
  check(error);
}

void StatsCsv::check(const std::string& local_error) const {
  if (comm_ != MPI_COMM_NULL) {
    throw_if_failed_anywhere(comm_, local_error);
  } else if (!local_error.empty()) {
    throw std::runtime_error(local_error);
  }
}

}  // namespace dipc
