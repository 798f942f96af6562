// predict makes a single built-in call that runs for many seconds without the engine
// looking at its clock: a naive search of a long string.
const haystack = 'a'.repeat(400000);
const needle = 'a'.repeat(200000) + 'b';
function predict(mu, sigma, u, R) {
  return haystack.indexOf(needle);
}
