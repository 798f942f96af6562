// predict returns null.
function predict(mu, sigma, u, R) {
  return null;
}
