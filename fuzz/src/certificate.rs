//! The certificate reader and `check` (single, scene, search and planar certificates), and the
//! region map checker, as `safereach check` runs them.
//!
//! Input: a certificate or region map (JSON). Properties: a certificate that checks Ok has
//! the verdict it states, and re-serialised (`to_json`) it reads back equal and checks Ok
//! with the same verdict and as many pieces (likewise a map, with the same leaves); a
//! refusal — unreadable, or invalid — says why in the user's terms. An edited input almost
//! always fails the digest first, so each input is also checked as a forger would send it,
//! with its digest recomputed, which reaches the proofs.

use safereach::proof::certificate_file::CertificateFile;
use safereach::proof::region_check::check_map;
use safereach::proof::region_map::RegionMap;

use super::assert_user_message;

fn certificate(cert: &CertificateFile, input: &str) {
    match cert.check() {
        Ok(report) => {
            assert_eq!(
                report.verdict,
                cert.verdict(),
                "checked Ok with another verdict"
            );
            let text = cert.to_json();
            let back = CertificateFile::from_json(&text).expect("a written certificate reads");
            assert_eq!(&back, cert, "a written certificate reads back different");
            let again = back.check().expect("a written valid certificate checks Ok");
            assert_eq!(again.verdict, report.verdict);
            assert_eq!(again.pieces, report.pieces);
        }
        Err(e) => assert_user_message(&e.to_string(), input),
    }
}

fn forged(cert: &CertificateFile) -> Option<CertificateFile> {
    let computed = match cert {
        CertificateFile::Single(c) => c.compute_digest(),
        CertificateFile::Scene(c) => c.compute_digest(),
        CertificateFile::Search(c) => c.compute_digest(),
        CertificateFile::Planar(c) => c.compute_digest(),
    };
    let mut cert = cert.clone();
    let stated = match &mut cert {
        CertificateFile::Single(c) => &mut c.digest,
        CertificateFile::Scene(c) => &mut c.digest,
        CertificateFile::Search(c) => &mut c.digest,
        CertificateFile::Planar(c) => &mut c.digest,
    };
    if *stated == computed {
        return None;
    }
    *stated = computed;
    Some(cert)
}

fn map(map: &RegionMap, input: &str) {
    match check_map(map) {
        Ok(report) => {
            let text = serde_json::to_string_pretty(map).expect("maps serialise");
            let back: RegionMap = serde_json::from_str(&text).expect("a written map reads");
            assert_eq!(&back, map, "a written map reads back different");
            let again = check_map(&back).expect("a written valid map checks Ok");
            assert_eq!(again.leaves, report.leaves);
            assert_eq!(again.all_certified, report.all_certified);
        }
        Err(e) => assert_user_message(&e.to_string(), input),
    }
}

/// The `certificate` target's body (see the module docs).
pub fn fuzz_certificate(data: &[u8]) {
    let Ok(input) = std::str::from_utf8(data) else {
        return;
    };
    match CertificateFile::from_json(input) {
        Ok(cert) => {
            certificate(&cert, input);
            if let Some(cert) = forged(&cert) {
                certificate(&cert, input);
            }
        }
        Err(e) => assert_user_message(&e.to_string(), input),
    }
    if let Ok(mut m) = serde_json::from_str::<RegionMap>(input) {
        map(&m, input);
        let digest = m.compute_digest();
        if m.digest != digest {
            m.digest = digest;
            map(&m, input);
        }
    }
}
