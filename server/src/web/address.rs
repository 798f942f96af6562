//! Who a client is counted as, by the connection limits and the sign-in limits alike:
//! an IPv4 address itself, and an IPv6 client by its /64, which one client usually holds
//! whole (an IPv4 address mapped into IPv6 is that IPv4 address).

use axum::extract::ConnectInfo;
use axum::http::request::Parts;
use std::net::{IpAddr, Ipv4Addr, SocketAddr};

/// The block `address` is counted in.
pub fn block(address: IpAddr) -> IpAddr {
    match address {
        IpAddr::V4(_) => address,
        IpAddr::V6(v6) => match v6.to_ipv4_mapped() {
            Some(v4) => IpAddr::V4(v4),
            None => IpAddr::V6((u128::from(v6) & !((1u128 << 64) - 1)).into()),
        },
    }
}

/// The client's address: the peer's, or behind a proxy the last address it added.
pub fn client_address(parts: &Parts, behind_https: bool) -> IpAddr {
    let forwarded = behind_https
        .then(|| {
            parts
                .headers
                .get_all("x-forwarded-for")
                .iter()
                .filter_map(|v| v.to_str().ok())
                .flat_map(|v| v.split(','))
                .next_back()
                .and_then(|last| last.trim().parse().ok())
        })
        .flatten();
    forwarded.unwrap_or_else(|| {
        parts
            .extensions
            .get::<ConnectInfo<SocketAddr>>()
            .map_or(IpAddr::V4(Ipv4Addr::UNSPECIFIED), |info| info.0.ip())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ip(text: &str) -> IpAddr {
        text.parse().unwrap()
    }

    #[test]
    fn an_ipv6_client_is_its_slash_64_and_a_mapped_ipv4_its_ipv4() {
        assert_eq!(block(ip("2001:db8:1:2:ffff::9")), ip("2001:db8:1:2::"));
        assert_eq!(
            block(ip("2001:db8:1:2::1")),
            block(ip("2001:db8:1:2:abcd::1"))
        );
        assert_ne!(block(ip("2001:db8:1:2::1")), block(ip("2001:db8:1:3::1")));
        assert_eq!(block(ip("::ffff:192.0.2.7")), ip("192.0.2.7"));
        assert_eq!(block(ip("192.0.2.7")), ip("192.0.2.7"));
    }
}
