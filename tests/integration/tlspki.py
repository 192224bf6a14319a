# SPDX-License-Identifier: MIT
"""The TLS test material shared by test_tls.py and test_security.py: a CA
and certificates made with the cryptography package (the role in its
extension OID 1.3.6.1.4.1.50316.802.1, a UTF8String), a daemon started
with a TLS listener, and a client context. The pki fixture is in
conftest.py."""

import datetime
import re
import ssl

from cryptography import x509
from cryptography.hazmat.primitives import hashes, serialization
from cryptography.hazmat.primitives.asymmetric import ec
from cryptography.x509.oid import NameOID

ROLE_OID = x509.ObjectIdentifier("1.3.6.1.4.1.50316.802.1")
NOW = datetime.datetime.now(datetime.timezone.utc)
DAY = datetime.timedelta(days=1)


def utf8string(text):
    """DER of an ASN.1 UTF8String (short form: the roles are short)."""
    raw = text.encode()
    assert len(raw) < 128
    return bytes([0x0C, len(raw)]) + raw


def make_ca(name):
    key = ec.generate_private_key(ec.SECP256R1())
    subject = x509.Name([x509.NameAttribute(NameOID.COMMON_NAME, name)])
    cert = (x509.CertificateBuilder().subject_name(subject).issuer_name(subject)
            .public_key(key.public_key()).serial_number(x509.random_serial_number())
            .not_valid_before(NOW - DAY).not_valid_after(NOW + 30 * DAY)
            .add_extension(x509.BasicConstraints(ca=True, path_length=None), critical=True)
            .add_extension(x509.KeyUsage(digital_signature=True, key_cert_sign=True,
                                         crl_sign=True, content_commitment=False,
                                         key_encipherment=False, data_encipherment=False,
                                         key_agreement=False, encipher_only=False,
                                         decipher_only=False), critical=True)
            .sign(key, hashes.SHA256()))
    return key, cert


def make_cert(ca, name, role=None, server=False, expired=False, role_der=None):
    ca_key, ca_cert = ca
    key = ec.generate_private_key(ec.SECP256R1())
    b = (x509.CertificateBuilder()
         .subject_name(x509.Name([x509.NameAttribute(NameOID.COMMON_NAME, name)]))
         .issuer_name(ca_cert.subject).public_key(key.public_key())
         .serial_number(x509.random_serial_number()))
    if expired:
        b = b.not_valid_before(NOW - 30 * DAY).not_valid_after(NOW - DAY)
    else:
        b = b.not_valid_before(NOW - DAY).not_valid_after(NOW + 30 * DAY)
    if server:
        import ipaddress
        b = b.add_extension(x509.SubjectAlternativeName(
            [x509.IPAddress(ipaddress.ip_address("127.0.0.1"))]), critical=False)
    if role is not None or role_der is not None:
        b = b.add_extension(x509.UnrecognizedExtension(
            ROLE_OID, role_der if role_der is not None else utf8string(role)), critical=False)
    return key, b.sign(ca_key, hashes.SHA256())


def save(tmp, stem, key, cert):
    kp, cp = tmp / f"{stem}.key", tmp / f"{stem}.pem"
    kp.write_bytes(key.private_bytes(serialization.Encoding.PEM,
                                     serialization.PrivateFormat.PKCS8,
                                     serialization.NoEncryption()))
    cp.write_bytes(cert.public_bytes(serialization.Encoding.PEM))
    return str(cp), str(kp)


def make_pki(tmp):
    """A CA, the server's certificate and one client certificate per case
    the tests need, as files under @p tmp: {name: (cert, key)}, "ca": path."""
    ca = make_ca("pneufrac test CA")
    other = make_ca("another CA")
    (tmp / "ca.pem").write_bytes(ca[1].public_bytes(serialization.Encoding.PEM))
    files = {"ca": str(tmp / "ca.pem"),
             "server": save(tmp, "server", *make_cert(ca, "pneufracd", server=True))}
    for role in ("viewer", "operator", "engineer", "auditor", "intruder"):
        files[role] = save(tmp, role, *make_cert(ca, f"client {role}", role=role))
    files["norole"] = save(tmp, "norole", *make_cert(ca, "client without role"))
    files["expired"] = save(tmp, "expired", *make_cert(ca, "old", role="engineer",
                                                       expired=True))
    files["otherca"] = save(tmp, "otherca", *make_cert(other, "stranger", role="engineer"))
    files["badder"] = save(tmp, "badder", *make_cert(ca, "bad role encoding",
                                                     role_der=b"\x13\x08engineer"))
    return files


def start(daemon, pki, *extra):
    d = daemon("--tls-listen", "127.0.0.1:0", "--tls-cert", pki["server"][0],
               "--tls-key", pki["server"][1], "--tls-ca", pki["ca"],
               "--tls-roles", "viewer:read,operator:operate,engineer:engineer,auditor:none",
               *extra)
    d.tls_port = int(re.search(r"msg=listening-tls addr=\S+ port=(\d+)", d.log()).group(1))
    return d


def client_ctx(pki, who, max_version=None):
    ctx = ssl.SSLContext(ssl.PROTOCOL_TLS_CLIENT)
    # pymodbus wraps its socket without a server name, so the chain is
    # verified (CERT_REQUIRED) but not the name.
    ctx.check_hostname = False
    ctx.load_verify_locations(pki["ca"])
    if who is not None:
        ctx.load_cert_chain(*pki[who])
    if max_version is not None:
        ctx.maximum_version = max_version
    return ctx
