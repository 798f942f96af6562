// observation_model throws a Proxy of an Error whose getPrototypeOf trap throws an Error
// in the host's own words for a stack overflow.
function observation_model(x, M, j) {
  const error = new Error('recursion is fine');
  throw new Proxy(error, { getPrototypeOf() { throw new Error('stack overflow'); } });
}
