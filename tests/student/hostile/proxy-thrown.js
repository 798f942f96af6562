// update throws a Proxy whose getPrototypeOf trap throws the Proxy itself: instanceof on
// it throws it again.
function update(mu_bar, sigma_bar, H, S, nu) {
  const proxy = new Proxy({}, { getPrototypeOf() { throw proxy; } });
  throw proxy;
}
