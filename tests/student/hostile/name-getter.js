// The thrown error's name is a string when first read and, when read again, an object of
// length 1 that turns into a megabyte of text: unbounded text from a single clip.
function shifty(message) {
  const error = new Error(message);
  let reads = 0;
  Object.defineProperty(error, 'name', {
    get() {
      reads++;
      return reads === 1 ? 'Error' : { length: 1, toString: () => 'N'.repeat(1 << 20) };
    },
  });
  return error;
}
function predict(mu, sigma, u, R) { throw shifty('shifty name'); }
function update(mu_bar, sigma_bar, H, S, nu) { throw shifty('shifty name'); }
function batch_update(mu_bar, sigma_bar, H_bar, Q_bar, nu_bar) { throw shifty('shifty name'); }
function associate(mu_bar, sigma_bar, z, M, Lambda_M, Q) { throw shifty('shifty name'); }
