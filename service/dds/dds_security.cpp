#include "service/dds/dds_security.hpp"

#include <cstdio>
#include <filesystem>
#include <memory>

#include <openssl/bio.h>
#include <openssl/pem.h>
#include <openssl/x509.h>

namespace skyroute::dds {

const char* const kSecurityFiles[6] = {"identity_ca.pem",    "identity.pem",   "identity.key",
                                       "permissions_ca.pem", "governance.p7s", "permissions.p7s"};

namespace {

struct X509Free {
  void operator()(X509* x) const { X509_free(x); }
};
struct KeyFree {
  void operator()(EVP_PKEY* k) const { EVP_PKEY_free(k); }
};
using CertificatePtr = std::unique_ptr<X509, X509Free>;
using KeyPtr = std::unique_ptr<EVP_PKEY, KeyFree>;

std::string fileOf(const std::string& dir, const char* name) { return (std::filesystem::path(dir) / name).string(); }

template <typename T, typename Read>
T readPem(const std::string& path, Read read) {
  std::FILE* f = std::fopen(path.c_str(), "r");
  if (f == nullptr) return T();
  T value(read(f));
  std::fclose(f);
  return value;
}

CertificatePtr readCertificate(const std::string& path) {
  return readPem<CertificatePtr>(path, [](std::FILE* f) { return PEM_read_X509(f, nullptr, nullptr, nullptr); });
}

std::string printTime(const ASN1_TIME* t) {
  std::unique_ptr<BIO, decltype(&BIO_free)> bio(BIO_new(BIO_s_mem()), &BIO_free);
  if (!bio || ASN1_TIME_print(bio.get(), t) != 1) return "?";
  char* data = nullptr;
  const long n = BIO_get_mem_data(bio.get(), &data);
  return std::string(data, static_cast<std::size_t>(n));
}

// A certificate in force now, and signed by `ca` when given.
Status checkCertificate(const std::string& path, const X509* certificate, X509* ca, const std::string& ca_path) {
  if (X509_cmp_current_time(X509_get0_notAfter(certificate)) < 0) {
    return make_error(ErrorCode::kInvalidArgument, path, "the certificate expired on " + printTime(X509_get0_notAfter(certificate)));
  }
  if (X509_cmp_current_time(X509_get0_notBefore(certificate)) > 0) {
    return make_error(ErrorCode::kInvalidArgument, path,
                      "the certificate is not valid before " + printTime(X509_get0_notBefore(certificate)));
  }
  if (ca != nullptr && X509_verify(const_cast<X509*>(certificate), X509_get0_pubkey(ca)) != 1) {
    return make_error(ErrorCode::kInvalidArgument, path,
                      "the certificate is not signed by " + ca_path + " (it comes from another certificate authority)");
  }
  return Status::success();
}

}  // namespace

Status checkSecurityFolder(const std::string& dir) {
  for (const char* name : kSecurityFiles) {
    const std::string path = fileOf(dir, name);
    std::FILE* f = std::fopen(path.c_str(), "r");
    if (f == nullptr) {
      return make_error(ErrorCode::kInvalidArgument, path,
                        "cannot read " + std::string(name) + " of the security folder (scripts/make-pki.sh makes it)");
    }
    std::fclose(f);
  }
  const std::string ca_path = fileOf(dir, "identity_ca.pem");
  const std::string identity_path = fileOf(dir, "identity.pem");
  const std::string permissions_ca_path = fileOf(dir, "permissions_ca.pem");
  CertificatePtr ca = readCertificate(ca_path);
  CertificatePtr identity = readCertificate(identity_path);
  CertificatePtr permissions_ca = readCertificate(permissions_ca_path);
  for (const auto& [certificate, path] : {std::pair{ca.get(), ca_path}, std::pair{identity.get(), identity_path},
                                          std::pair{permissions_ca.get(), permissions_ca_path}}) {
    if (certificate == nullptr) return make_error(ErrorCode::kInvalidArgument, path, "is not a PEM certificate");
  }
  if (Status s = checkCertificate(ca_path, ca.get(), nullptr, ""); !s.ok()) return s;
  if (Status s = checkCertificate(permissions_ca_path, permissions_ca.get(), nullptr, ""); !s.ok()) return s;
  if (Status s = checkCertificate(identity_path, identity.get(), ca.get(), ca_path); !s.ok()) return s;
  const std::string key_path = fileOf(dir, "identity.key");
  KeyPtr key = readPem<KeyPtr>(key_path, [](std::FILE* f) { return PEM_read_PrivateKey(f, nullptr, nullptr, nullptr); });
  if (!key) return make_error(ErrorCode::kInvalidArgument, key_path, "is not an unencrypted PEM private key");
  if (X509_check_private_key(identity.get(), key.get()) != 1) {
    return make_error(ErrorCode::kInvalidArgument, key_path, "is not the key of " + identity_path);
  }
  return Status::success();
}

void addSecurityProperties(dds_qos_t* qos, const std::string& dir) {
  const std::string root = std::filesystem::absolute(dir).string();
  auto file = [&](const char* name) { return "file:" + fileOf(root, name); };
  // Each plugin: its library (found by short name where Debian installs Cyclone's) and entry points.
  const char* const plugins[][4] = {
      {"auth", "dds_security_auth", "init_authentication", "finalize_authentication"},
      {"crypto", "dds_security_crypto", "init_crypto", "finalize_crypto"},
      {"access", "dds_security_ac", "init_access_control", "finalize_access_control"},
  };
  for (const auto& [plugin, library, init, finalize] : plugins) {
    const std::string prefix = std::string("dds.sec.") + plugin + ".library.";
    dds_qset_prop(qos, (prefix + "path").c_str(), library);
    dds_qset_prop(qos, (prefix + "init").c_str(), init);
    dds_qset_prop(qos, (prefix + "finalize").c_str(), finalize);
  }
  const char* const files[][2] = {
      {"dds.sec.auth.identity_ca", "identity_ca.pem"},     {"dds.sec.auth.identity_certificate", "identity.pem"},
      {"dds.sec.auth.private_key", "identity.key"},        {"dds.sec.access.permissions_ca", "permissions_ca.pem"},
      {"dds.sec.access.governance", "governance.p7s"},     {"dds.sec.access.permissions", "permissions.p7s"},
  };
  for (const auto& [property, name] : files) dds_qset_prop(qos, property, file(name).c_str());
}

}  // namespace skyroute::dds
