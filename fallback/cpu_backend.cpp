#include "fallback/cpu_backend.h"

#include <stdexcept>

#include "fallback/cpu_triangle_operators.h"

namespace harmonia::detail {
namespace {

// The CPU backend only ever receives its own objects; anything else is a programming error.
const CpuMatrix& cpu(const DeviceMatrix& matrix) {
  const auto* result = dynamic_cast<const CpuMatrix*>(&matrix);
  if (result == nullptr) throw std::logic_error("cpu backend: matrix from another backend");
  return *result;
}
const CpuVectors& cpu(const DeviceVectors& vectors) {
  const auto* result = dynamic_cast<const CpuVectors*>(&vectors);
  if (result == nullptr) throw std::logic_error("cpu backend: vectors from another backend");
  return *result;
}
CpuVectors& cpu(DeviceVectors& vectors) {
  auto* result = dynamic_cast<CpuVectors*>(&vectors);
  if (result == nullptr) throw std::logic_error("cpu backend: vectors from another backend");
  return *result;
}

void check_shapes(const DeviceVectors& x, const DeviceVectors& y, const char* operation) {
  if (x.rows() != y.rows() || x.cols() != y.cols())
    throw std::invalid_argument(std::string("cpu backend: ") + operation + ": block shapes differ");
}

}  // namespace

CpuMatrix::CpuMatrix(const RowMajorSparse& matrix) : matrix_(matrix) {
  matrix_.makeCompressed();
  refresh_diagonal();
}

void CpuMatrix::update_values(const Eigen::Ref<const Eigen::VectorXd>& csr_values) {
  if (csr_values.size() != matrix_.nonZeros())
    throw std::invalid_argument("cpu backend: update_values: wrong number of values");
  Eigen::Map<Eigen::VectorXd>(matrix_.valuePtr(), matrix_.nonZeros()) = csr_values;
  refresh_diagonal();
}

void CpuMatrix::refresh_diagonal() {
  inverse_diagonal_ = Eigen::VectorXd::Ones(matrix_.rows());
  for (int row = 0; row < matrix_.outerSize(); ++row) {
    for (RowMajorSparse::InnerIterator entry(matrix_, row); entry; ++entry) {
      if (entry.col() == row && entry.value() != 0.0) inverse_diagonal_[row] = 1.0 / entry.value();
    }
  }
}

void CpuVectors::upload(const Eigen::Ref<const Eigen::MatrixXd>& values) {
  if (values.rows() != values_.rows() || values.cols() != values_.cols())
    throw std::invalid_argument("cpu backend: upload: block shape differs");
  values_ = values;
}

std::string CpuBackend::description() const {
#ifdef HARMONIA_HAVE_CHOLMOD
  return "cpu (eigen, cholmod)";
#else
  return "cpu (eigen)";
#endif
}

bool CpuBackend::supports(Feature feature) const {
  switch (feature) {
    case Feature::float64:
      return true;
    case Feature::direct_factorization:
      return true;
  }
  return false;
}

std::unique_ptr<DeviceMatrix> CpuBackend::upload(const RowMajorSparse& matrix) {
  return std::make_unique<CpuMatrix>(matrix);
}

std::unique_ptr<DeviceVectors> CpuBackend::upload(const Eigen::Ref<const Eigen::MatrixXd>& values) {
  return std::make_unique<CpuVectors>(values);
}

std::unique_ptr<DeviceVectors> CpuBackend::allocate(int rows, int cols) {
  return std::make_unique<CpuVectors>(rows, cols);
}

void CpuBackend::spmv(const DeviceMatrix& a, const DeviceVectors& x, DeviceVectors& y) {
  const RowMajorSparse& matrix = cpu(a).matrix();
  if (matrix.cols() != x.rows() || matrix.rows() != y.rows() || x.cols() != y.cols())
    throw std::invalid_argument("cpu backend: spmv: shapes differ");
  cpu(y).values().noalias() = matrix * cpu(x).values();
}

Eigen::VectorXd CpuBackend::dot(const DeviceVectors& x, const DeviceVectors& y) {
  check_shapes(x, y, "dot");
  return cpu(x).values().cwiseProduct(cpu(y).values()).colwise().sum().transpose();
}

void CpuBackend::axpy(const Eigen::VectorXd& alpha, const DeviceVectors& x, DeviceVectors& y) {
  check_shapes(x, y, "axpy");
  cpu(y).values() += cpu(x).values() * alpha.asDiagonal();
}

void CpuBackend::xpay(const DeviceVectors& x, const Eigen::VectorXd& beta, DeviceVectors& y) {
  check_shapes(x, y, "xpay");
  Eigen::MatrixXd& target = cpu(y).values();
  target = cpu(x).values() + target * beta.asDiagonal();
}

void CpuBackend::copy(const DeviceVectors& x, DeviceVectors& y) {
  check_shapes(x, y, "copy");
  cpu(y).values() = cpu(x).values();
}

void CpuBackend::jacobi(const DeviceMatrix& a, const DeviceVectors& r, DeviceVectors& z) {
  check_shapes(r, z, "jacobi");
  const Eigen::VectorXd& inverse_diagonal = cpu(a).inverse_diagonal();
  if (inverse_diagonal.size() != r.rows())
    throw std::invalid_argument("cpu backend: jacobi: shapes differ");
  cpu(z).values() = inverse_diagonal.asDiagonal() * cpu(r).values();
}

std::unique_ptr<TriangleOperators> CpuBackend::triangle_operators(const Eigen::MatrixX3i& faces,
                                                                 int vertex_count) {
  return std::make_unique<CpuTriangleOperators>(faces, vertex_count);
}

}  // namespace harmonia::detail
