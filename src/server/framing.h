/* framing.h — refuses requests whose length or target a proxy in front could read
 * differently from libmicrohttpd (RFC 9112 §6.3), before any body byte is read. */
#ifndef TC_SERVER_FRAMING_H
#define TC_SERVER_FRAMING_H

#include <stddef.h>

#include <microhttpd.h>

/* 0 if the request's framing is unambiguous; else 1, with what is wrong in
 * detail[0..n). version: the request line's ("HTTP/1.1"). Such a request is
 * answered 400 and its connection closed: the bytes after it cannot be trusted. */
int tc_framing_error(struct MHD_Connection *c, const char *version, char *detail, size_t n);

#endif
