//! Whether an executable is statically linked: a package's binary must run on whatever
//! C library the platform's image has, so it may name no dynamic loader.

/// `PT_INTERP`: the program header naming the dynamic loader a program needs.
const PT_INTERP: u32 = 3;

/// Whether `bytes`, a 64-bit little-endian ELF executable (x86-64 Linux), needs no
/// dynamic loader; an error says what else it is.
pub fn is_static(bytes: &[u8]) -> Result<bool, String> {
    if bytes.len() < 64 || &bytes[..4] != b"\x7fELF" {
        return Err("not an ELF executable".to_owned());
    }
    if bytes[4] != 2 || bytes[5] != 1 {
        return Err("not a 64-bit little-endian ELF executable".to_owned());
    }
    let u16_at = |at: usize| u16::from_le_bytes([bytes[at], bytes[at + 1]]) as usize;
    let u32_at = |at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().expect("4 bytes"));
    let u64_at =
        |at: usize| u64::from_le_bytes(bytes[at..at + 8].try_into().expect("8 bytes")) as usize;
    // The ELF header: e_phoff at 0x20, e_phentsize at 0x36, e_phnum at 0x38.
    let (offset, size, count) = (u64_at(0x20), u16_at(0x36), u16_at(0x38));
    let end = offset
        .checked_add(size.checked_mul(count).ok_or("program headers overflow")?)
        .ok_or("program headers overflow")?;
    if size < 4 || end > bytes.len() {
        return Err("its program headers lie outside the file".to_owned());
    }
    Ok((0..count).all(|i| u32_at(offset + i * size) != PT_INTERP))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_dynamic_program_names_its_loader() {
        // The shell of this machine is dynamically linked.
        let shell = std::fs::read("/bin/sh").unwrap();
        assert_eq!(is_static(&shell), Ok(false));
        assert!(is_static(b"#!/bin/sh\necho hi\n").is_err());
        let mut truncated = shell[..64].to_vec();
        truncated[0x20..0x28].copy_from_slice(&u64::MAX.to_le_bytes());
        assert!(is_static(&truncated).is_err());
    }
}
