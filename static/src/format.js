// Numbers for people: a few significant digits, exponents only where they help.

/** `value` with `digits` significant digits: 0.0123, 1.5e-5, 1234. */
export function fmt(value, digits = 4) {
  if (!Number.isFinite(value)) return String(value);
  if (value === 0) return '0';
  const magnitude = Math.abs(value);
  if (magnitude >= 1e-3 && magnitude < 1e5) return String(Number(value.toPrecision(digits)));
  return value.toExponential(digits - 1).replace(/\.?0+e/, 'e');
}

/**
 * `value` rounded to 12 significant digits: the number a person meant by it, without the
 * float noise of the arithmetic that made it (0.2 ** 2 = 0.04000000000000001 is 0.04).
 * Its shortest form (String) then reads back as the same number.
 */
export function decimal(value) {
  return Number.isFinite(value) ? Number(value.toPrecision(12)) : value;
}
