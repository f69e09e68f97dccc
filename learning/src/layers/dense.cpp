#include "dc/learning/layers/dense.hpp"

#include "dc/core/error.hpp"
#include "dc/learning/initializer.hpp"

namespace dc {

namespace {
using MatMap = Eigen::Map<Eigen::MatrixXf>;
using CMatMap = Eigen::Map<const Eigen::MatrixXf>;
}  // namespace

Dense::Dense(int in_features, Shape out, bool relu) : in_(in_features), out_(out), relu_(relu) {
  out_.n = 1;
  if (in_ <= 0 || out_.c <= 0 || out_.h <= 0 || out_.w <= 0)
    throw InvalidArgument("Dense: in_features and output shape must be positive, got " + std::to_string(in_) +
                          " -> " + out_.str());
  out_features_ = static_cast<int>(out_.sample_count());
  weight_ = Tensor(out_features_, in_, 1, 1);
  dweight_ = Tensor(out_features_, in_, 1, 1);
  bias_ = Tensor(1, out_features_, 1, 1);
  dbias_ = Tensor(1, out_features_, 1, 1);
}

std::string Dense::describe() const {
  return "dense " + std::to_string(in_) + "->[" + std::to_string(out_.c) + "," + std::to_string(out_.h) + "," +
         std::to_string(out_.w) + "]" + (relu_ ? " relu" : "");
}

Shape Dense::output_shape(const Shape& in) const {
  if (static_cast<long>(in.sample_count()) != in_)
    throw InvalidArgument("Dense (" + describe() + "): input " + in.str() + " has " +
                          std::to_string(in.sample_count()) + " features");
  return out_.with_batch(in.n);
}

void Dense::forward(const Tensor& x, Tensor& y, bool /*training*/) {
  y.resize(output_shape(x.shape()));
  const int N = x.n();
  const CMatMap Wt(weight_.data(), in_, out_features_);
  const CMatMap X(x.data(), in_, N);
  MatMap Y(y.data(), out_features_, N);
  Y.noalias() = Wt.transpose() * X;
  Y.colwise() += Eigen::Map<const Eigen::VectorXf>(bias_.data(), out_features_);
  if (relu_) Y = Y.cwiseMax(0.0f);
}

void Dense::backward(const Tensor& x, const Tensor& y, const Tensor& dy, Tensor* dx) {
  const Shape out = output_shape(x.shape());
  require_shape(dy.shape(), out, "Dense::backward dy");
  const int N = x.n();
  const float* g = dy.data();
  if (relu_) {
    require_shape(y.shape(), out, "Dense::backward y");
    masked_.resize(out);
    masked_.flat() = (y.flat().array() > 0.0f).select(dy.flat(), 0.0f);
    g = masked_.data();
  }
  const CMatMap G(g, out_features_, N);
  const CMatMap X(x.data(), in_, N);
  MatMap dWt(dweight_.data(), in_, out_features_);
  dWt.noalias() = X * G.transpose();
  Eigen::Map<Eigen::VectorXf>(dbias_.data(), out_features_) = G.rowwise().sum();
  if (dx != nullptr) {
    dx->resize(x.shape());
    MatMap(dx->data(), in_, N).noalias() = CMatMap(weight_.data(), in_, out_features_) * G;
  }
}

std::vector<ParamRef> Dense::parameters() {
  return {{"weight", &weight_, &dweight_, true}, {"bias", &bias_, &dbias_, false}};
}

void Dense::initialize(const Initializer& init, Rng& rng) {
  init.fill(weight_, in_, out_features_, rng);
  bias_.set_zero();
}

}  // namespace dc
