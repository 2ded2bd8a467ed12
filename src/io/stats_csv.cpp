// StatsCsv: per-step statistics table (see stats_csv.hpp).
#include "io/stats_csv.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "io/collective_error.hpp"

namespace dipc {

StatsCsv::StatsCsv(const std::string& path, std::vector<std::string> columns, MPI_Comm comm)
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
    file_.reset(std::fopen(path_.c_str(), "w"));
    if (!file_) {
      error = "cannot create '" + path_ + "': " + std::strerror(errno);
    } else {
      std::string header;
      for (const std::string& c : columns_) header += (header.empty() ? "" : ",") + c;
      header += "\n";
      if (std::fputs(header.c_str(), file_.get()) < 0 || std::fflush(file_.get()) != 0) {
        error = "cannot write '" + path_ + "': " + std::strerror(errno);
      }
    }
  }
  check(error);
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
    throw std::invalid_argument("StatsCsv '" + path_ + "': row has " + std::to_string(values.size()) +
                                " values for " + std::to_string(columns_.size()) + " columns");
  }
  std::string error;
  if (writes_) {
    bool ok = true;
    for (std::size_t i = 0; i < values.size(); ++i) {
      ok = ok && (i == 0 || std::fputc(',', file_.get()) != EOF) && std::fputs(values[i].csv().c_str(), file_.get()) >= 0;
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
