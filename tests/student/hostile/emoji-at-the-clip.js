// predict, correct, throws for the cases whose control turns the robot left by over
// 0.3 rad, with a message whose 300th character is the first half of an emoji's
// surrogate pair.
predict = (function (correct) {
  return function (mu, sigma, u, R) {
    if (u[2] > 0.3) throw new Error('x'.repeat(299) + '\u{1F600} and more');
    return correct(mu, sigma, u, R);
  };
})(predict);
